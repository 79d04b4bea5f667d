//! `pps-trials`: the paper's experiment (§V, Table I) in the simulator against a registry.
//!
//! The protocol: each device, the robot starting 1.5 m from its tag at the paper's four
//! directions, each action, and the failure cases (unplugged lamp, stuck drawer for pull and for
//! push, sticky object), where a success is a correctly *detected* failure. `--randomized K`
//! runs K trials drawn from the same rows with random start poses, tag placement and noise.
//! Every trial goes through the robot's outbox; the command exits only once the registry holds
//! all of them.
//!
//! The randomized sweep is a benchmark, not a test (it takes minutes):
//! `pps-trials --server URL --token T --robot el-e-1 --randomized 1000 --seed 1`.
//! `RUST_LOG=pps_robot=debug` prints the full report of every trial that missed.

use std::time::Duration;

use clap::Args;
use pps_schema::Outcome;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::json;

use super::registry_args::RegistryArgs;
use super::run::{Fault, SimulatedTrial, run_simulated, start_up};
use crate::registry::RegistryClient;
use crate::sim::{DeviceKind, RoomOptions, StartDirection};
use crate::task::TaskConfig;

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

/// One row of Table I: a device, a scenario, and the paper's figure for it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Protocol {
    pub device: DeviceKind,
    /// The paper's name for the row.
    pub scenario: &'static str,
    pub action: &'static str,
    pub fault: Option<Fault>,
    /// The paper's successes out of 4.
    pub paper: u32,
}

/// Table I's rows, in the paper's order.
pub const TABLE_ONE: [Protocol; 12] = [
    Protocol {
        device: DeviceKind::LightSwitch,
        scenario: "switching on",
        action: "on",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::LightSwitch,
        scenario: "switching off",
        action: "off",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::AdaLightSwitch,
        scenario: "switching on",
        action: "on",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::AdaLightSwitch,
        scenario: "switching off",
        action: "off",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::Lamp,
        scenario: "switching on",
        action: "on",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::Lamp,
        scenario: "detect switching failure",
        action: "on",
        fault: Some(Fault::LampUnplugged),
        paper: 4,
    },
    Protocol {
        device: DeviceKind::TrashCan,
        scenario: "drop object into",
        action: "drop",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::TrashCan,
        scenario: "detect dropping failure",
        action: "drop",
        fault: Some(Fault::StickyObject),
        paper: 4,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "pull open",
        action: "open",
        fault: None,
        paper: 3,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "push closed",
        action: "close",
        fault: None,
        paper: 3,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "detect pulling failure",
        action: "open",
        fault: Some(Fault::DrawerStuck),
        paper: 2,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "detect pushing failure",
        action: "close",
        fault: Some(Fault::DrawerStuck),
        paper: 3,
    },
];

/// Our result for one row.
#[derive(Debug, Clone, PartialEq)]
pub struct TableRow {
    pub protocol: Protocol,
    pub successes: u32,
    pub trials: u32,
    /// One line per trial that did not count as a success, saying why.
    pub misses: Vec<String>,
}

/// Whether a trial counts: on a normal row, the robot declared success and the room changed;
/// on a failure row, the robot declared failure and the room indeed did not change.
fn counts(protocol: &Protocol, outcome: Option<Outcome>, achieved: bool) -> bool {
    match protocol.fault {
        None => outcome == Some(Outcome::Success) && achieved,
        Some(_) => outcome == Some(Outcome::Failure) && !achieved,
    }
}

/// Runs the protocol (or `randomized` random trials) in `room` and returns the table.
pub async fn run_trials(
    registry: &RegistryClient,
    room: RoomOptions,
    seed: u64,
    randomized: Option<usize>,
    progress: bool,
) -> anyhow::Result<Vec<TableRow>> {
    let mut rows: Vec<TableRow> = TABLE_ONE
        .iter()
        .map(|p| TableRow { protocol: *p, successes: 0, trials: 0, misses: Vec::new() })
        .collect();
    let body = start_up(registry).await?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let plan: Vec<(usize, SimulatedTrial)> = match randomized {
        None => TABLE_ONE
            .iter()
            .enumerate()
            .flat_map(|(i, p)| {
                StartDirection::PAPER.into_iter().enumerate().map(move |(k, direction)| {
                    let trial = SimulatedTrial {
                        start_angle: direction.angle(),
                        seed: seed.wrapping_mul(1000) + (i * 4 + k) as u64,
                        body,
                        room,
                        ..SimulatedTrial::new(p.device, p.action, p.fault)
                    };
                    (i, trial)
                })
            })
            .collect(),
        Some(k) => (0..k)
            .map(|n| {
                let i = rng.random_range(0..TABLE_ONE.len());
                let p = &TABLE_ONE[i];
                let trial = SimulatedTrial {
                    // Anywhere on the paper's half-circle and its ends (±67.5°), nearer or further.
                    start_angle: rng.random_range(-67.5f64..67.5).to_radians(),
                    start_distance: rng.random_range(1.2..2.0),
                    // Tags where homes put them: the switches higher or lower, the rocker
                    // along the wall (but not over the sideboard, where no robot could stand
                    // to reach it), the lamp and the trash can along their walls (clear of the
                    // furniture beside them).
                    // In a home the switches keep their tags 25–35 cm apart.
                    room: RoomOptions {
                        switch_spacing: if room.switch_spacing < 1.0 {
                            rng.random_range(0.25..0.35)
                        } else {
                            rng.random_range(2.2..2.9)
                        },
                        switch_raise: rng.random_range(-0.08..0.08),
                        lamp_along: rng.random_range(4.3..4.7),
                        trash_can_along: rng.random_range(2.35..3.2),
                        ..room
                    },
                    seed: seed.wrapping_mul(1_000_003) + n as u64,
                    body,
                    ..SimulatedTrial::new(p.device, p.action, p.fault)
                };
                (i, trial)
            })
            .collect(),
    };
    let config = TaskConfig::default();
    for (n, (row, trial)) in plan.iter().enumerate() {
        let result = run_simulated(trial, registry, &config).await?;
        let row = &mut rows[*row];
        row.trials += 1;
        let ok = counts(&row.protocol, result.report.outcome, result.achieved);
        if ok {
            row.successes += 1;
        } else {
            tracing::debug!("missed trial:\n{}", result.report);
            let stopped = result.report.phases.iter().find(|p| !p.ok).map(|p| {
                format!(
                    "stopped in phase {}: {}",
                    p.phase,
                    p.lines.last().cloned().unwrap_or_default()
                )
            });
            row.misses.push(format!(
                "{} {} from {:.0}° (seed {}): outcome {:?}, room changed: {}{}",
                trial.device.type_name(),
                trial.action,
                trial.start_angle.to_degrees(),
                trial.seed,
                result.report.outcome.map(Outcome::as_str),
                result.achieved,
                stopped.map(|s| format!(", {s}")).unwrap_or_default()
            ));
        }
        if progress {
            tracing::info!(
                "[{}/{}] {} {}: {}",
                n + 1,
                plan.len(),
                trial.device.type_name(),
                row.protocol.scenario,
                if ok { "ok" } else { "MISS" }
            );
        }
    }
    Ok(rows)
}

/// Uploads what the outbox holds, waiting while the registry is unreachable.
pub async fn flush_until_stored(registry: &RegistryClient) -> anyhow::Result<()> {
    let mut wait = Duration::from_millis(500);
    loop {
        let report = registry.flush().await?;
        if report.remaining == 0 {
            return Ok(());
        }
        tracing::warn!(
            "{} trial(s) waiting for the registry; retrying in {:?}",
            report.remaining,
            wait
        );
        tokio::time::sleep(wait).await;
        wait = (wait * 2).min(Duration::from_secs(10));
    }
}

fn paper_name(device: DeviceKind) -> &'static str {
    match device {
        DeviceKind::LightSwitch => "Flip-type light switch",
        DeviceKind::AdaLightSwitch => "ADA rocker light switch",
        DeviceKind::Lamp => "Lamp",
        DeviceKind::TrashCan => "Trash can",
        DeviceKind::Drawer => "Cabinet drawer",
    }
}

/// The table beside the paper's figures.
pub fn render_table(rows: &[TableRow], randomized: bool) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "{:<26} {:<26} {:>9} {:>8}\n",
        "PPS-tagged object", "scenario", "ours", "paper"
    ));
    let (mut ours, mut trials, mut paper) = (0, 0, 0);
    for row in rows.iter().filter(|r| r.trials > 0) {
        let rate = 100.0 * f64::from(row.successes) / f64::from(row.trials);
        out.push_str(&format!(
            "{:<26} {:<26} {:>4}/{:<4} {:>4}/4   ({rate:.0}%)\n",
            paper_name(row.protocol.device),
            row.protocol.scenario,
            row.successes,
            row.trials,
            row.protocol.paper
        ));
        ours += row.successes;
        trials += row.trials;
        paper += row.protocol.paper;
    }
    let paper_total = if randomized { String::from("-") } else { format!("{paper}/48") };
    out.push_str(&format!("{:<53} {:>4}/{:<4} {:>6}\n", "all", ours, trials, paper_total));
    for row in rows {
        for miss in &row.misses {
            out.push_str(&format!("miss: {miss}\n"));
        }
    }
    out
}

pub fn rows_json(rows: &[TableRow]) -> serde_json::Value {
    json!({
        "rows": rows.iter().filter(|r| r.trials > 0).map(|r| json!({
            "device": r.protocol.device.type_name(),
            "scenario": r.protocol.scenario,
            "successes": r.successes,
            "trials": r.trials,
        })).collect::<Vec<_>>()
    })
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
