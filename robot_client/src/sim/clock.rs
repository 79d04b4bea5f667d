//! Virtual time: devices advance it by how long their motion would take; nothing sleeps.
//! [`SimClock`] turns it into trial timestamps.

use std::time::Duration;

use time::OffsetDateTime;

use super::robot::SimRobot;
use crate::hal::Clock;

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

/// Trial times in the simulator: the real time the run started plus the virtual time elapsed,
/// so trials carry plausible timestamps and durations that do not depend on the host's speed.
#[derive(Debug, Clone)]
pub struct SimClock {
    robot: SimRobot,
    epoch: OffsetDateTime,
}

impl SimClock {
    /// A clock for `robot` whose virtual zero is `epoch`.
    pub fn new(robot: SimRobot, epoch: OffsetDateTime) -> Self {
        let elapsed = robot.state().clock.now();
        Self { robot, epoch: epoch - elapsed }
    }
}

impl Clock for SimClock {
    fn now(&self) -> OffsetDateTime {
        self.epoch + self.robot.state().clock.now()
    }
}
