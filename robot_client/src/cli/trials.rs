//! `pps-trials`: the paper's experiment ([`crate::experiment`]) from the command line, its table
//! printed beside the paper's figures. `--randomized K` runs K trials drawn from Table I's rows
//! with random start poses, tag placement and noise. The command exits only once the registry
//! holds every trial.
//!
//! The randomized sweep is a benchmark, not a test (it takes minutes):
//! `pps-trials --server URL --token T --robot el-e-1 --randomized 1000 --seed 1`.
//! `RUST_LOG=pps_robot=debug` prints the full report of every trial that missed.

use clap::Args;

use super::registry_args::RegistryArgs;
use crate::experiment::{flush_until_stored, render_table, rows_json, run_trials};
use crate::sim::RoomOptions;

#[derive(Debug, Args)]
pub struct TrialsArgs {
    #[command(flatten)]
    pub registry: RegistryArgs,
    /// Seed of the simulated world's noise (and, with --randomized, of the trials drawn).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Instead of the protocol, K trials with random start poses, tag placement and noise.
    #[arg(long)]
    pub randomized: Option<usize>,
    /// Print one JSON document `{"rows": [...]}` and nothing else on stdout.
    #[arg(long)]
    pub json: bool,
    /// The simulated room: paper (the paper's lab) or home (red things beside the tags, the
    /// switches' tags 30 cm apart, lacquered fronts, evening light).
    #[arg(long, default_value = "paper", value_parser = RoomOptions::named)]
    pub room: RoomOptions,
}

pub fn run(args: &TrialsArgs) -> anyhow::Result<()> {
    let registry = args.registry.connect()?;
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build()?;
    runtime.block_on(async {
        // A robot at work for minutes follows the change feed, so it uses its cached entries
        // without asking each time and still sees a caretaker's edit.
        let _watch = registry.watch_changes();
        let rows = run_trials(&registry, args.room, args.seed, args.randomized, true).await?;
        flush_until_stored(&registry).await?;
        if args.json {
            println!("{}", rows_json(&rows));
        } else {
            print!("{}", render_table(&rows, args.randomized.is_some()));
        }
        anyhow::Ok(())
    })
}
