//! `pps-robot`: parses the command line and hands it to the library.

use std::process::ExitCode;

use clap::Parser;
use pps_robot::cli::{Cli, init_logging, run};

fn main() -> ExitCode {
    init_logging();
    // The perception chain runs on this thread: it works beside the pool, not waiting on it.
    pps_robot::cores::work_on_this_thread();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
