//! When each robot was last seen: noted in memory on every robot request, flushed to the
//! database now and then, so a read never writes.
//!
//! Noting runs on the robots' hot path, on every core at once, so it is a shared read lock and,
//! at most once a second per robot, one atomic store: nothing is formatted and no lock is taken
//! for writing except when a robot is seen for the first time. A last-seen time is therefore
//! the first request of its second.

use std::collections::HashMap;
use std::sync::RwLock;
use std::sync::atomic::{AtomicBool, AtomicI64, Ordering};
use std::time::Duration;

use time::OffsetDateTime;

use crate::clock;

/// How finely a robot's last-seen time is kept.
const RESOLUTION_MS: i64 = 1000;

/// A robot seen within this long is online: a working robot claims or heartbeats far more
/// often.
pub const ONLINE_WITHIN: Duration = Duration::from_secs(60);

#[derive(Debug, Default)]
struct Seen {
    /// Unix time in milliseconds.
    at_ms: AtomicI64,
    /// Whether `at_ms` changed since the last flush.
    unflushed: AtomicBool,
}

impl Seen {
    fn note(&self, now_ms: i64) {
        if now_ms - self.at_ms.load(Ordering::Relaxed) >= RESOLUTION_MS {
            self.at_ms.store(now_ms, Ordering::Relaxed);
            self.unflushed.store(true, Ordering::Release);
        }
    }

    fn at(at_ms: i64) -> Self {
        Self { at_ms: AtomicI64::new(at_ms), unflushed: AtomicBool::new(false) }
    }

    fn formatted(&self) -> String {
        let at = OffsetDateTime::from_unix_timestamp_nanos(
            i128::from(self.at_ms.load(Ordering::Relaxed)) * 1_000_000,
        );
        at.map(clock::format).unwrap_or_default()
    }
}

#[derive(Debug, Default)]
pub struct Presence {
    /// Robot id → when it was last seen.
    seen: RwLock<HashMap<String, Seen>>,
}

impl Presence {
    /// Notes that `robot` was seen at `now`.
    pub fn saw(&self, robot: &str, now: OffsetDateTime) {
        let now_ms = unix_ms(now);
        if let Some(seen) = self.seen.read().unwrap_or_else(|e| e.into_inner()).get(robot) {
            seen.note(now_ms);
            return;
        }
        let mut seen = self.seen.write().unwrap_or_else(|e| e.into_inner());
        seen.entry(robot.to_owned()).or_default().note(now_ms);
    }

    /// Seeds the memory with what the database holds, at start.
    pub fn load(&self, stored: Vec<(String, String)>) {
        let mut seen = self.seen.write().unwrap_or_else(|e| e.into_inner());
        for (robot, at) in stored {
            let Some(at) = clock::parse(&at) else { continue };
            seen.entry(robot).or_insert_with(|| Seen::at(unix_ms(at)));
        }
    }

    pub fn last_seen(&self, robot: &str) -> Option<String> {
        let seen = self.seen.read().unwrap_or_else(|e| e.into_inner());
        seen.get(robot).map(Seen::formatted)
    }

    /// How long before `now` the robot was last seen; `None` when it never was.
    pub fn seen_ago(&self, robot: &str, now: OffsetDateTime) -> Option<Duration> {
        let seen = self.seen.read().unwrap_or_else(|e| e.into_inner());
        let at_ms = seen.get(robot)?.at_ms.load(Ordering::Relaxed);
        let ago_ms = unix_ms(now) - at_ms;
        Some(Duration::from_millis(u64::try_from(ago_ms).unwrap_or(0)))
    }

    /// Whether the robot was seen within [`ONLINE_WITHIN`] before `now`.
    pub fn online(&self, robot: &str, now: OffsetDateTime) -> bool {
        self.seen_ago(robot, now).is_some_and(|ago| ago <= ONLINE_WITHIN)
    }

    /// The sightings not yet flushed, marking them flushed.
    pub fn take_unflushed(&self) -> Vec<(String, String)> {
        let seen = self.seen.read().unwrap_or_else(|e| e.into_inner());
        seen.iter()
            .filter(|(_, seen)| seen.unflushed.swap(false, Ordering::Acquire))
            .map(|(robot, seen)| (robot.clone(), seen.formatted()))
            .collect()
    }
}

fn unix_ms(at: OffsetDateTime) -> i64 {
    (at.unix_timestamp_nanos() / 1_000_000) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_robot_seen_is_flushed_once_until_seen_again() {
        let presence = Presence::default();
        let now = OffsetDateTime::now_utc();
        assert!(presence.take_unflushed().is_empty());
        presence.saw("el-e-1", now);
        let flushed = presence.take_unflushed();
        assert_eq!(flushed.len(), 1);
        assert_eq!(flushed[0].0, "el-e-1");
        assert!(clock::parse(&flushed[0].1).is_some(), "{}", flushed[0].1);
        assert!(presence.take_unflushed().is_empty(), "nothing new to flush");
        assert_eq!(presence.last_seen("el-e-1"), Some(flushed[0].1.clone()));
        assert!(presence.online("el-e-1", now));
        assert!(!presence.online("el-e-1", now + ONLINE_WITHIN + Duration::from_secs(1)));
        assert!(!presence.online("pr2-1", now), "never seen");
    }

    #[test]
    fn stored_times_are_known_but_not_flushed_again() {
        let presence = Presence::default();
        let now = OffsetDateTime::now_utc();
        presence.load(vec![("pr2-1".into(), "2026-11-22T10:00:00.000Z".into())]);
        assert_eq!(presence.last_seen("pr2-1").as_deref(), Some("2026-11-22T10:00:00.000Z"));
        assert!(presence.take_unflushed().is_empty());
        assert!(!presence.online("pr2-1", now), "seen long ago");
        assert!(presence.seen_ago("pr2-1", now).is_some_and(|ago| ago > ONLINE_WITHIN));
        presence.saw("pr2-1", now);
        assert_eq!(presence.take_unflushed().len(), 1, "seen now, a second and more later");
    }
}
