//! `pps-robot rfid`: inventory rounds on a real reader and the tag choice of the task's phase 3;
//! with `--registry`, also the chosen tag's actions as this robot's effective entry has them.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Context;
use clap::Args;
use serde_json::{Value, json};

use super::registry_args::RegistryArgs;
use crate::hal::{RfidReader, TagRead};
use crate::navigation::{RfidIdentity, TagSignal, identify_among, tag_signals};
use crate::rfid::llrp::{LlrpReader, LlrpSettings};
use crate::rfid::m5e::{M5eReader, M5eSettings, Region};
use crate::task::TaskConfig;

/// Which reader, and how to read with it: shared by `rfid` and `run`.
#[derive(Debug, Clone, PartialEq)]
pub enum ReaderChoice {
    Llrp(String),
    M5e(String),
}

/// How each round reads.
#[derive(Debug, Args, Clone)]
pub struct ReadSettings {
    /// Antenna ports to read, as numbered on the reader, e.g. 1,2 (default: all for LLRP, 1
    /// for the M5e).
    #[arg(long, value_delimiter = ',')]
    pub antennas: Vec<u16>,
    /// How long one inventory round lasts, milliseconds (10 to 60000).
    #[arg(long, default_value_t = 200, value_parser = round_ms)]
    pub round_ms: u64,
    /// Read (transmit) power, dBm; default: the reader's own setting.
    #[arg(long)]
    pub power_dbm: Option<f64>,
    /// The M5e's regulatory region: na, eu, kr, in, jp, cn, au or nz.
    #[arg(long, default_value = "na", value_parser = parse_region)]
    pub region: Region,
    /// The M5e's serial speed.
    #[arg(long, default_value_t = 115_200)]
    pub baud: u32,
}

fn parse_region(name: &str) -> Result<Region, String> {
    Region::parse(name)
        .ok_or_else(|| format!("`{name}` is not one of na, eu, kr, in, jp, cn, au, nz"))
}

/// Connects to the reader and sets it up, so an unreachable one is known before any round.
pub fn open_reader(
    choice: &ReaderChoice,
    read: &ReadSettings,
) -> anyhow::Result<Box<dyn RfidReader>> {
    let round = Duration::from_millis(read.round_ms);
    Ok(match choice {
        ReaderChoice::Llrp(address) => Box::new(LlrpReader::connect(LlrpSettings {
            antennas: read.antennas.clone(),
            round,
            read_power_dbm: read.power_dbm,
            ..LlrpSettings::new(address)
        })?),
        ReaderChoice::M5e(device) => {
            let antennas = read
                .antennas
                .iter()
                .map(|&a| {
                    u8::try_from(a).map_err(|_| anyhow::anyhow!("the M5e has no antenna {a}"))
                })
                .collect::<anyhow::Result<_>>()?;
            Box::new(M5eReader::open(M5eSettings {
                baud: read.baud,
                region: read.region,
                antennas,
                read_power_dbm: read.power_dbm,
                round,
                ..M5eSettings::new(device)
            })?)
        }
    })
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("reader").required(true).args(["llrp", "m5e"])))]
pub struct RfidArgs {
    /// An LLRP reader, HOST[:PORT] (port 5084 unless given).
    #[arg(long)]
    pub llrp: Option<String>,
    /// A ThingMagic M5e on this serial device, e.g. /dev/ttyUSB0.
    #[arg(long)]
    pub m5e: Option<String>,
    #[command(flatten)]
    pub read: ReadSettings,
    /// Inventory rounds to read.
    #[arg(long, default_value_t = TaskConfig::default().rfid_rounds)]
    pub rounds: usize,
    /// The strongest tag must lead the next by this much, dB, or the read is ambiguous.
    #[arg(long, default_value_t = TaskConfig::default().rfid_margin_db)]
    pub margin_db: f64,
    /// Print one JSON document on stdout instead of text.
    #[arg(long)]
    pub json: bool,
    /// Also look the chosen tag up in this registry (base URL) as --robot.
    #[arg(long, requires_all = ["robot", "token"])]
    pub registry: Option<String>,
    /// The robot's API token, for --registry.
    #[arg(long, env = "PPS_TOKEN", hide_env_values = true)]
    pub token: Option<String>,
    /// The robot's id in the registry, for --registry.
    #[arg(long)]
    pub robot: Option<String>,
    /// A CA certificate (PEM) to trust for an HTTPS registry.
    #[arg(long, env = "PPS_CA_CERT")]
    pub ca_cert: Option<PathBuf>,
    /// Where the robot keeps its entry cache; default `pps-robot/<ROBOT>` in the system's
    /// temporary directory, as for `run`.
    #[arg(long)]
    pub state: Option<PathBuf>,
}

impl RfidArgs {
    fn choice(&self) -> ReaderChoice {
        match (&self.llrp, &self.m5e) {
            (Some(address), _) => ReaderChoice::Llrp(address.clone()),
            (None, Some(device)) => ReaderChoice::M5e(device.clone()),
            (None, None) => unreachable!("clap requires one of --llrp and --m5e"),
        }
    }
}

pub fn run(args: &RfidArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.rounds > 0, "--rounds must be at least 1");
    let reader = open_reader(&args.choice(), &args.read)?;
    let mut reads: Vec<TagRead> = Vec::new();
    for round in 1..=args.rounds {
        let got = reader.inventory().with_context(|| format!("inventory round {round}"))?;
        tracing::info!("round {round}: {} reads", got.len());
        reads.extend(got);
    }
    drop(reader);
    let signals = tag_signals(&reads);
    let identity = identify_among(signals.clone(), args.margin_db);
    let lookup = match (&args.registry, identity.as_ref()) {
        (Some(server), Some(identity)) => Some(look_up(args, server, identity.strongest())?),
        _ => None,
    };
    if args.json {
        let mut doc = json!({
            "reads": reads.iter().map(|r| json!({"epc": r.epc.as_hex(), "rssi_dbm": r.rssi_dbm, "antenna": r.antenna.0})).collect::<Vec<_>>(),
            "tags": signals.iter().map(|s| json!({"epc": s.epc.as_hex(), "rssi_dbm": s.rssi_dbm, "reads": s.reads})).collect::<Vec<_>>(),
            "chosen": identity.as_ref().map(|i| i.strongest().epc.as_hex()),
            "ambiguous": matches!(identity, Some(RfidIdentity::Ambiguous { .. })),
        });
        if let Some(lookup) = lookup {
            doc["registry"] = lookup;
        }
        println!("{doc}");
    } else {
        print!("{}", render(&signals, identity.as_ref(), args.margin_db, lookup.as_ref()));
    }
    Ok(())
}

/// The chosen tag's effective entry, as `{"revision", "name", "actions": {action: behaviour},
/// "unavailable_actions": [...]}`, or `{"error": sentence}` when the registry cannot say.
fn look_up(args: &RfidArgs, server: &str, chosen: &TagSignal) -> anyhow::Result<Value> {
    let registry = RegistryArgs {
        server: server.to_owned(),
        token: args.token.clone().unwrap_or_default(),
        ca_cert: args.ca_cert.clone(),
        robot: args.robot.clone().unwrap_or_default(),
        state: args.state.clone(),
    }
    .connect()?;
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build()?;
    Ok(match runtime.block_on(registry.effective_entry(&chosen.epc)) {
        Ok(fetched) => {
            let effective = fetched.entry;
            json!({
                "revision": effective.revision,
                "name": effective.entry.properties.name,
                "actions": effective.entry.actions,
                "unavailable_actions": effective.unavailable_actions.iter().map(|u| json!({"action": u.action, "reason": u.reason})).collect::<Vec<_>>(),
            })
        }
        Err(error) => json!({"error": error.to_string()}),
    })
}

fn render(
    signals: &[TagSignal],
    identity: Option<&RfidIdentity>,
    margin_db: f64,
    lookup: Option<&Value>,
) -> String {
    let mut out = String::new();
    if signals.is_empty() {
        out.push_str("no tag answered\n");
        return out;
    }
    out.push_str("tags, strongest first:\n");
    for s in signals {
        out.push_str(&format!("  {}  {:>6.1} dBm  {} reads\n", s.epc, s.rssi_dbm, s.reads));
    }
    match identity {
        Some(RfidIdentity::Identified(s)) => out.push_str(&format!("chosen: {}\n", s.epc)),
        Some(RfidIdentity::Ambiguous { strongest, runner_up }) => out.push_str(&format!(
            "chosen: {} (ambiguous: {} is within {margin_db} dB)\n",
            strongest.epc, runner_up.epc
        )),
        None => {}
    }
    if let Some(lookup) = lookup {
        if let Some(error) = lookup["error"].as_str() {
            out.push_str(&format!("registry: {error}\n"));
        } else {
            out.push_str(&format!(
                "registry: {} (revision {})\n",
                lookup["name"].as_str().unwrap_or("?"),
                lookup["revision"]
            ));
            let unavailable = lookup["unavailable_actions"].as_array().cloned().unwrap_or_default();
            for (action, behavior) in lookup["actions"].as_object().into_iter().flatten() {
                let why = unavailable
                    .iter()
                    .find(|u| u["action"] == *action)
                    .and_then(|u| u["reason"].as_str());
                out.push_str(&format!("  {action}: {}", behavior.as_str().unwrap_or("?")));
                if let Some(why) = why {
                    out.push_str(&format!(" (unavailable: {why})"));
                }
                out.push('\n');
            }
        }
    }
    out
}

/// A round's length in milliseconds: at least 10 (a reader needs that to inventory anything),
/// at most a minute (a round holds every read it keeps until it ends).
pub(super) fn round_ms(text: &str) -> Result<u64, String> {
    match text.trim().parse::<u64>() {
        Ok(ms) if (10..=60_000).contains(&ms) => Ok(ms),
        _ => Err(format!("{text:?} is not a round of 10 to 60000 milliseconds")),
    }
}
