//! When each robot was last seen: noted in memory on every robot request, flushed to the
//! database now and then, so a read never writes.

use std::collections::HashMap;
use std::sync::Mutex;

use crate::clock;

#[derive(Debug, Default)]
pub struct Presence {
    /// Robot id → last seen, and whether that is not yet flushed.
    seen: Mutex<HashMap<String, (String, bool)>>,
}

impl Presence {
    pub fn saw(&self, robot: &str) {
        let now = clock::now();
        let mut seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        match seen.get_mut(robot) {
            Some(entry) => *entry = (now, true),
            None => {
                seen.insert(robot.to_owned(), (now, true));
            }
        }
    }

    /// Seeds the memory with what the database holds, at start.
    pub fn load(&self, stored: Vec<(String, String)>) {
        let mut seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        for (robot, at) in stored {
            seen.entry(robot).or_insert((at, false));
        }
    }

    pub fn last_seen(&self, robot: &str) -> Option<String> {
        let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        seen.get(robot).map(|(at, _)| at.clone())
    }

    /// The sightings not yet flushed, marking them flushed.
    pub fn take_unflushed(&self) -> Vec<(String, String)> {
        let mut seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        seen.iter_mut()
            .filter(|(_, (_, dirty))| *dirty)
            .map(|(robot, (at, dirty))| {
                *dirty = false;
                (robot.clone(), at.clone())
            })
            .collect()
    }
}
