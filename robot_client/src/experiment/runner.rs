//! The experiment run end to end: start-up, every planned trial in a fresh room, each scored
//! into its row, and the outbox flushed until the registry holds every trial.

use std::time::Duration;

use pps_schema::Purpose;

use super::sampling::{PlannedTrial, plan};
use super::scoring::TableRow;
use super::start_up::start_up;
use super::table::TABLE_ONE;
use super::trial::run_simulated;
use crate::registry::RegistryClient;
use crate::sim::RoomOptions;
use crate::task::TaskConfig;

/// Runs the protocol (or `randomized` random trials) in `room` and returns the table.
pub async fn run_trials(
    registry: &RegistryClient,
    room: RoomOptions,
    seed: u64,
    randomized: Option<usize>,
    progress: bool,
) -> anyhow::Result<Vec<TableRow>> {
    let mut rows: Vec<TableRow> = TABLE_ONE.iter().map(|p| TableRow::empty(*p)).collect();
    let body = start_up(registry).await?;
    let plan = plan(seed, randomized, body, room);
    // The protocol fails on purpose (an unplugged lamp, a stuck drawer): its trials must not
    // count against the tags in real use.
    let config = TaskConfig { purpose: Purpose::Experiment, ..TaskConfig::default() };
    for (n, PlannedTrial { row, trial }) in plan.iter().enumerate() {
        let result = run_simulated(trial, registry, &config).await?;
        let row = &mut rows[*row];
        let ok = row.score(trial, &result);
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
        #[allow(clippy::disallowed_methods, reason = "back-off while the registry is unreachable")]
        tokio::time::sleep(wait).await;
        wait = (wait * 2).min(Duration::from_secs(10));
    }
}
