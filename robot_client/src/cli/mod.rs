//! The `pps-robot` command line: one module per subcommand, each an `Args` struct and a `run`.
//! The binary only parses and dispatches, so adding a subcommand is one variant here.

// The commands that set up a simulated world come with the `sim` feature; the others work on
// recorded data and real readers, on a robot whose software leaves the simulator out.
#[cfg(feature = "sim")]
mod bench;
mod bench_llrp;
mod logging;
#[cfg(feature = "sim")]
mod parse;
mod perceive;
mod registry_args;
mod rfid;
#[cfg(feature = "sim")]
mod run;
#[cfg(feature = "sim")]
mod scene;
#[cfg(feature = "sim")]
mod trials;
#[cfg(feature = "sim")]
mod work;

use clap::{Parser, Subcommand};

pub use crate::picture::draw_overlay;
#[cfg(feature = "sim")]
pub use bench::BenchArgs;
pub use bench_llrp::BenchLlrpArgs;
pub use logging::init_logging;
pub use perceive::{PerceiveArgs, PerceiveReport};
pub use registry_args::RegistryArgs;
pub use rfid::{ReadSettings, ReaderChoice, RfidArgs, open_reader};
#[cfg(feature = "sim")]
pub use run::RunArgs;
#[cfg(feature = "sim")]
pub use scene::SceneArgs;
#[cfg(feature = "sim")]
pub use trials::{TrialsArgs, run as trials_main};
#[cfg(feature = "sim")]
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
    #[cfg(feature = "sim")]
    /// Export a simulated scene (image.png, cloud.ply, camera.json, scene.json) to try
    /// `perceive` on.
    Scene(SceneArgs),
    #[cfg(feature = "sim")]
    /// One task in the simulator against a registry, printed phase by phase.
    Run(RunArgs),
    #[cfg(feature = "sim")]
    /// A simulated robot doing the tasks caretakers ask the registry for, one after another.
    Work(WorkArgs),
    /// Inventory rounds on a real RFID reader (LLRP or ThingMagic M5e) and the tag choice.
    Rfid(RfidArgs),
    #[cfg(feature = "sim")]
    /// Time each perception step and the whole chain on the fixed benchmark scene.
    BenchPerception(BenchArgs),
    /// Time LLRP report decoding, and inventory rounds on a reader.
    BenchLlrp(BenchLlrpArgs),
}

/// Runs one parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Perceive(args) => perceive::run(&args),
        #[cfg(feature = "sim")]
        Command::Scene(args) => scene::run(&args),
        #[cfg(feature = "sim")]
        Command::BenchPerception(args) => bench::run(&args),
        Command::BenchLlrp(args) => bench_llrp::run(&args),
        #[cfg(feature = "sim")]
        Command::Run(args) => run::run(&args),
        #[cfg(feature = "sim")]
        Command::Work(args) => work::run(&args),
        Command::Rfid(args) => rfid::run(&args),
    }
}
