//! `pps-trials`: the paper's Table I protocol in the simulator against a registry.

use std::process::ExitCode;

use clap::Parser;
use pps_robot::cli::TrialsArgs;

/// Runs the paper's experiment (Table I) in the simulator and records every trial.
#[derive(Debug, Parser)]
#[command(
    name = "pps-trials",
    version,
    about = "The paper's Table I experiment in the simulator, every trial recorded in the registry"
)]
struct Cli {
    #[command(flatten)]
    args: TrialsArgs,
}

fn main() -> ExitCode {
    pps_robot::cli::init_logging();
    // The perception chain runs on this thread: it works beside the pool, not waiting on it.
    pps_robot::cores::work_on_this_thread();
    match pps_robot::cli::trials_main(&Cli::parse().args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
