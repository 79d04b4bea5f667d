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

    fn moment(&self) -> OffsetDateTime {
        let ns = i128::from(self.at_ms.load(Ordering::Relaxed)) * 1_000_000;
        OffsetDateTime::from_unix_timestamp_nanos(ns).unwrap_or(OffsetDateTime::UNIX_EPOCH)
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
    pub fn load(&self, stored: Vec<(String, OffsetDateTime)>) {
        let mut seen = self.seen.write().unwrap_or_else(|e| e.into_inner());
        for (robot, at) in stored {
            seen.entry(robot).or_insert_with(|| Seen::at(unix_ms(at)));
        }
    }

    pub fn last_seen(&self, robot: &str) -> Option<OffsetDateTime> {
        let seen = self.seen.read().unwrap_or_else(|e| e.into_inner());
        seen.get(robot).map(Seen::moment)
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
    pub fn take_unflushed(&self) -> Vec<(String, OffsetDateTime)> {
        let seen = self.seen.read().unwrap_or_else(|e| e.into_inner());
        seen.iter()
            .filter(|(_, seen)| seen.unflushed.swap(false, Ordering::Acquire))
            .map(|(robot, seen)| (robot.clone(), seen.moment()))
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
        let now = time::macros::datetime!(2026-11-22 10:00:00.250 UTC);
        assert!(presence.take_unflushed().is_empty());
        presence.saw("el-e-1", now);
        assert_eq!(presence.take_unflushed(), [("el-e-1".to_owned(), now)]);
        assert!(presence.take_unflushed().is_empty(), "nothing new to flush");
        presence.saw("el-e-1", now + Duration::from_millis(500));
        assert!(presence.take_unflushed().is_empty(), "kept to the second");
        assert_eq!(presence.last_seen("el-e-1"), Some(now));
        assert!(presence.online("el-e-1", now));
        assert!(!presence.online("el-e-1", now + ONLINE_WITHIN + Duration::from_secs(1)));
        assert!(!presence.online("pr2-1", now), "never seen");
    }

    #[test]
    fn stored_times_are_known_but_not_flushed_again() {
        let presence = Presence::default();
        let now = OffsetDateTime::now_utc();
        let long_ago = time::macros::datetime!(2026-11-22 10:00 UTC);
        presence.load(vec![("pr2-1".into(), long_ago)]);
        assert_eq!(presence.last_seen("pr2-1"), Some(long_ago));
        assert!(presence.take_unflushed().is_empty());
        assert!(!presence.online("pr2-1", now), "seen long ago");
        assert!(presence.seen_ago("pr2-1", now).is_some_and(|ago| ago > ONLINE_WITHIN));
        presence.saw("pr2-1", now);
        assert_eq!(presence.take_unflushed().len(), 1, "seen now, a second and more later");
    }
}
