//! The `pps-robot` command line: one module per subcommand, each an `Args` struct and a `run`.
//! The binary only parses and dispatches, so adding a subcommand is one variant here.

mod bench;
mod bench_llrp;
mod logging;
mod parse;
mod perceive;
mod registry_args;
mod rfid;
mod run;
mod scene;
mod trials;
mod work;

use clap::{Parser, Subcommand};

pub use crate::picture::draw_overlay;
pub use bench::BenchArgs;
pub use bench_llrp::BenchLlrpArgs;
pub use logging::init_logging;
pub use perceive::{PerceiveArgs, PerceiveReport};
pub use registry_args::RegistryArgs;
pub use rfid::{ReadSettings, ReaderChoice, RfidArgs, open_reader};
pub use run::RunArgs;
pub use scene::SceneArgs;
pub use trials::{TrialsArgs, run as trials_main};
pub use work::WorkArgs;

/// The robot side of PPS-tags.
#[derive(Debug, Parser)]
#[command(name = "pps-robot", version, about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Perception and navigation geometry on a recorded image, cloud and camera calibration.
    // Boxed: its parsed colour thresholds carry their lookup table.
    Perceive(Box<PerceiveArgs>),
    /// Export a simulated scene (image.png, cloud.ply, camera.json, scene.json) to try
    /// `perceive` on.
    Scene(SceneArgs),
    /// One task in the simulator against a registry, printed phase by phase.
    Run(RunArgs),
    /// A simulated robot doing the tasks caretakers ask the registry for, one after another.
    Work(WorkArgs),
    /// Inventory rounds on a real RFID reader (LLRP or ThingMagic M5e) and the tag choice.
    Rfid(RfidArgs),
    /// Time each perception step and the whole chain on the fixed benchmark scene.
    BenchPerception(BenchArgs),
    /// Time LLRP report decoding, and inventory rounds on a reader.
    BenchLlrp(BenchLlrpArgs),
}

/// Runs one parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Perceive(args) => perceive::run(&args),
        Command::Scene(args) => scene::run(&args),
        Command::BenchPerception(args) => bench::run(&args),
        Command::BenchLlrp(args) => bench_llrp::run(&args),
        Command::Run(args) => run::run(&args),
        Command::Work(args) => work::run(&args),
        Command::Rfid(args) => rfid::run(&args),
    }
}
