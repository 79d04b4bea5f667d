//! `pps-robot run`: one task in the simulator against a registry, printed phase by phase.
//!
//! The trial is set up and run by [`crate::experiment`]; this command only reads its settings
//! from the command line, opens a real reader if asked, and prints the robot's report.

use clap::Args;

use super::parse::{parse_device, parse_direction};
use super::registry_args::RegistryArgs;
use super::rfid::{ReadSettings, ReaderChoice, open_reader};
use crate::experiment::{Fault, SimulatedTrial, run_simulated_reading, start_up};
use crate::sim::{DeviceKind, RoomOptions, StartDirection};
use crate::task::TaskConfig;

#[derive(Debug, Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub registry: RegistryArgs,
    /// light-switch, ada-light-switch, lamp, drawer or trash-can.
    #[arg(long, value_parser = parse_device)]
    pub device: DeviceKind,
    /// The action the person wants, as the entry names it (on, off, open, close, drop).
    #[arg(long)]
    pub action: String,
    /// Seed of the simulated world's noise (and, with --randomized, of the trials drawn).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Where the robot starts, 1.5 m from the tag: far-left, left, front, right or far-right.
    #[arg(long = "from", default_value = "front", value_parser = parse_direction)]
    pub from: StartDirection,
    /// A failure to inject: lamp-unplugged, drawer-stuck or sticky-object.
    #[arg(long, value_parser = parse_fault)]
    pub fault: Option<Fault>,
    /// The simulated room: paper (the paper's lab) or home (red things beside the tags, the
    /// switches' tags 30 cm apart, lacquered fronts, evening light).
    #[arg(long, default_value = "paper", value_parser = RoomOptions::named)]
    pub room: RoomOptions,
    /// Phase 3 reads a real LLRP reader, HOST[:PORT], instead of the simulated fingers.
    #[arg(long, conflicts_with = "rfid_m5e")]
    pub rfid_llrp: Option<String>,
    /// Phase 3 reads a real ThingMagic M5e on this serial device.
    #[arg(long)]
    pub rfid_m5e: Option<String>,
    #[command(flatten)]
    pub rfid_read: ReadSettings,
    /// Send the trial without a picture of what the camera saw around the tag.
    #[arg(long)]
    pub no_picture: bool,
}

fn parse_fault(name: &str) -> Result<Fault, String> {
    match name {
        "lamp-unplugged" => Ok(Fault::LampUnplugged),
        "drawer-stuck" => Ok(Fault::DrawerStuck),
        "sticky-object" => Ok(Fault::StickyObject),
        _ => Err(format!("`{name}` is not one of lamp-unplugged, drawer-stuck, sticky-object")),
    }
}

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let registry = args.registry.connect()?;
    let choice = match (&args.rfid_llrp, &args.rfid_m5e) {
        (Some(address), _) => Some(ReaderChoice::Llrp(address.clone())),
        (None, Some(device)) => Some(ReaderChoice::M5e(device.clone())),
        (None, None) => None,
    };
    // Connected before the task starts, so an unreachable reader stops it at once.
    let reader = choice.map(|c| open_reader(&c, &args.rfid_read)).transpose()?;
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build()?;
    let result = runtime.block_on(async {
        let trial = SimulatedTrial {
            start_angle: args.from.angle(),
            seed: args.seed,
            room: args.room,
            body: start_up(&registry).await?,
            ..SimulatedTrial::new(args.device, &args.action, args.fault)
        };
        let config = TaskConfig { picture: !args.no_picture, ..TaskConfig::default() };
        run_simulated_reading(&trial, &registry, &config, reader.as_deref()).await
    })?;
    tracing::info!("state directory: {}", args.registry.state_dir().display());
    print!("{}", result.report);
    Ok(())
}
