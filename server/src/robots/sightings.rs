//! Unknown EPCs that robots read, gathered in memory and written to the inbox in the
//! background (within a second), so a robot's 404 costs no database write.

use std::collections::HashMap;
use std::sync::Mutex;

use time::OffsetDateTime;

use crate::store::inbox::Sighting;

#[derive(Debug, Default)]
pub struct Sightings {
    pending: Mutex<HashMap<String, Sighting>>,
}

/// Unknown EPCs kept between flushes, so a flood of random EPCs cannot grow memory unbounded.
const MAX_PENDING: usize = 10_000;

impl Sightings {
    /// Notes that `robot` read the unknown `epc` at `at`.
    pub fn note(&self, epc: &str, robot: &str, at: OffsetDateTime) {
        let mut pending = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(sighting) = pending.get_mut(epc) {
            sighting.count += 1;
            sighting.last_seen = at;
            if !sighting.robots.iter().any(|r| r == robot) {
                sighting.robots.push(robot.to_owned());
            }
        } else if pending.len() < MAX_PENDING {
            pending.insert(
                epc.to_owned(),
                Sighting {
                    epc: epc.to_owned(),
                    robots: vec![robot.to_owned()],
                    first_seen: at,
                    last_seen: at,
                    count: 1,
                },
            );
        }
    }

    pub fn take(&self) -> Vec<Sighting> {
        let mut pending = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        pending.drain().map(|(_, sighting)| sighting).collect()
    }
}
