//! Wall-clock time of each compute step, in the order they ran: what `perceive --json` reports as
//! `timings_ms` and what the benchmark prints.

use std::time::Instant;

use serde::ser::{Serialize, SerializeMap, Serializer};

/// Milliseconds per named step, in run order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepTimings {
    steps: Vec<(&'static str, f64)>,
}

impl StepTimings {
    /// Runs `step`, adding its duration under `name` (to any earlier time under that name).
    pub fn time<T>(&mut self, name: &'static str, step: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let out = step();
        self.add(name, start.elapsed().as_secs_f64() * 1e3);
        out
    }

    /// Adds `ms` under `name` (to any earlier time under that name).
    pub fn add(&mut self, name: &'static str, ms: f64) {
        match self.steps.iter_mut().find(|(n, _)| *n == name) {
            Some((_, total)) => *total += ms,
            None => self.steps.push((name, ms)),
        }
    }

    pub fn steps(&self) -> &[(&'static str, f64)] {
        &self.steps
    }

    pub fn get(&self, name: &str) -> Option<f64> {
        self.steps.iter().find(|(n, _)| *n == name).map(|(_, ms)| *ms)
    }

    /// The sum of every step, milliseconds.
    pub fn total_ms(&self) -> f64 {
        self.steps.iter().map(|(_, ms)| ms).sum()
    }
}

impl Serialize for StepTimings {
    /// A JSON object whose keys keep the order the steps ran in.
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.steps.len()))?;
        for (name, ms) in &self.steps {
            map.serialize_entry(name, ms)?;
        }
        map.end()
    }
}
