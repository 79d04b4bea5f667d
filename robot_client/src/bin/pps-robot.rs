//! `pps-robot`: parses the command line and hands it to the library.

use std::process::ExitCode;

use clap::Parser;
use pps_robot::cli::{Cli, init_logging, run};

fn main() -> ExitCode {
    init_logging();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
