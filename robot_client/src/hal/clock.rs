//! Time as a capability: trials carry the robot's own timestamps, and the simulator's time is
//! virtual, so a behaviour never reads the host's clock itself.

use time::OffsetDateTime;

/// Where trial times come from: the wall clock on a robot, the simulator's virtual clock.
pub trait Clock: Send + Sync {
    fn now(&self) -> OffsetDateTime;
}

/// Real time.
#[derive(Debug, Clone, Copy, Default)]
pub struct WallClock;

impl Clock for WallClock {
    fn now(&self) -> OffsetDateTime {
        OffsetDateTime::now_utc()
    }
}
