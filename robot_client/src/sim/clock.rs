//! Virtual time: devices advance it by how long their motion would take; nothing sleeps.
//! [`super::SimClock`] turns it into trial timestamps.

use std::time::Duration;

/// The simulator's time since it started, advanced by what happens in it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord)]
pub struct VirtualClock {
    now: Duration,
}

impl VirtualClock {
    pub fn now(&self) -> Duration {
        self.now
    }

    pub fn advance(&mut self, by: Duration) {
        self.now += by;
    }

    /// Advances by the time a motion of `distance` takes at `speed` (same units per second).
    pub fn advance_motion(&mut self, distance: f64, speed: f64) {
        if speed > 0.0 && distance.is_finite() {
            self.advance(Duration::from_secs_f64(distance.abs() / speed));
        }
    }
}
