//! `pps-robot work`: a simulated robot that does what caretakers ask (DESIGN §8).
//!
//! The loop is [`crate::worker`]; here are its settings, the signals (SIGTERM or Ctrl-C lets the
//! task at hand finish first) and the printing: a line per task on stdout, pauses on stderr.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use clap::Args;

use super::registry_args::RegistryArgs;
use crate::experiment::start_up;
use crate::sim::RoomOptions;
use crate::worker::{Said, Worker};

#[derive(Debug, Args)]
pub struct WorkArgs {
    #[command(flatten)]
    pub registry: RegistryArgs,
    /// Seed of the simulated world's noise; the n-th task runs with SEED + n.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Stop after this many tasks.
    #[arg(long, value_name = "N")]
    pub max_tasks: Option<u64>,
    /// Stop once no task came for this many seconds (at most a week).
    #[arg(long, value_name = "SECONDS")]
    pub idle_exit: Option<f64>,
    /// The simulated room: paper or home (as for `run`).
    #[arg(long, default_value = "paper", value_parser = RoomOptions::named)]
    pub room: RoomOptions,
    /// Send trials without a picture of what the camera saw around the tag.
    #[arg(long)]
    pub no_picture: bool,
}

/// The longest `--idle-exit`, seconds.
const MAX_IDLE_EXIT_SECONDS: f64 = 7.0 * 86_400.0;

pub fn run(args: &WorkArgs) -> anyhow::Result<()> {
    // A week is already "never"; far beyond, the clock cannot count it and the worker panics.
    if args.idle_exit.is_some_and(|s| !(0.0..=MAX_IDLE_EXIT_SECONDS).contains(&s)) {
        anyhow::bail!("--idle-exit takes 0 to {MAX_IDLE_EXIT_SECONDS} seconds (a week)");
    }
    let registry = args.registry.connect()?;
    // Heartbeats run on the workers while the simulation computes on this thread.
    let runtime =
        tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    runtime.block_on(async {
        let stopping = stop_on_signal()?;
        let worker = Worker {
            body: start_up(&registry).await?,
            registry,
            room: args.room,
            seed: args.seed,
            max_tasks: args.max_tasks,
            idle_exit: args.idle_exit.map(Duration::from_secs_f64),
            picture: !args.no_picture,
        };
        let done = worker
            .work(&stopping, |said| match said {
                Said::Task(line) => println!("{line}"),
                Said::Pause(line) => eprintln!("{line}"),
            })
            .await?;
        eprintln!("did {done} task(s)");
        anyhow::Ok(())
    })
}

/// Sets the flag on SIGTERM or Ctrl-C; the loop looks at it between tasks.
fn stop_on_signal() -> anyhow::Result<Arc<AtomicBool>> {
    let stopping = Arc::new(AtomicBool::new(false));
    let mut terminate = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())?;
    let flag = stopping.clone();
    tokio::spawn(async move {
        tokio::select! {
            _ = terminate.recv() => {}
            _ = tokio::signal::ctrl_c() => {}
        }
        eprintln!("asked to stop: finishing the task at hand first");
        flag.store(true, Ordering::Release);
    });
    Ok(stopping)
}
