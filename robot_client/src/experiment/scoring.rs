//! Scoring: whether a trial counts as a success of its row, and the line saying why one did not.

use pps_schema::Outcome;

use super::table::Protocol;
use super::trial::{SimulatedResult, SimulatedTrial};

/// Our result for one row.
#[derive(Debug, Clone, PartialEq)]
pub struct TableRow {
    pub protocol: Protocol,
    pub successes: u32,
    pub trials: u32,
    /// One line per trial that did not count as a success, saying why.
    pub misses: Vec<String>,
}

impl TableRow {
    /// The row before any of its trials ran.
    pub fn empty(protocol: Protocol) -> Self {
        Self { protocol, successes: 0, trials: 0, misses: Vec::new() }
    }

    /// Adds one trial of this row; returns whether it counted as a success.
    pub fn score(&mut self, trial: &SimulatedTrial, result: &SimulatedResult) -> bool {
        self.trials += 1;
        let ok = counts(&self.protocol, result.report.outcome, result.achieved);
        if ok {
            self.successes += 1;
        } else {
            tracing::debug!("missed trial:\n{}", result.report);
            self.misses.push(miss(trial, result));
        }
        ok
    }
}

/// Whether a trial counts: on a normal row, the robot declared success and the room changed;
/// on a failure row, the robot declared failure and the room indeed did not change.
fn counts(protocol: &Protocol, outcome: Option<Outcome>, achieved: bool) -> bool {
    match protocol.fault {
        None => outcome == Some(Outcome::Success) && achieved,
        Some(_) => outcome == Some(Outcome::Failure) && !achieved,
    }
}

/// The trial that missed, what the robot said and the room did, and the phase it stopped in.
fn miss(trial: &SimulatedTrial, result: &SimulatedResult) -> String {
    let stopped = result.report.phases.iter().find(|p| !p.ok).map(|p| {
        format!("stopped in phase {}: {}", p.phase, p.lines.last().cloned().unwrap_or_default())
    });
    format!(
        "{} {} from {:.0}° (seed {}): outcome {:?}, room changed: {}{}",
        trial.device.type_name(),
        trial.action,
        trial.start_angle.to_degrees(),
        trial.seed,
        result.report.outcome.map(Outcome::as_str),
        result.achieved,
        stopped.map(|s| format!(", {s}")).unwrap_or_default()
    )
}
