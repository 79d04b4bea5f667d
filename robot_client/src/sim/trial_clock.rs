//! The simulated robot's virtual time as trial timestamps.

use time::OffsetDateTime;

use super::robot::SimRobot;
use crate::hal::Clock;

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
