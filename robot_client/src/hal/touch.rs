//! Contact sensing in the hand: force-torque sensors at the base of each finger and the IR
//! range sensor in the palm.

use nalgebra::Vector3;

use super::HalError;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Finger {
    Left,
    Right,
}

/// A force (newtons) and torque (newton-metres) measured at a finger's base, in the base frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Wrench {
    pub force: Vector3<f64>,
    pub torque: Vector3<f64>,
}

impl Wrench {
    /// Magnitude of the force, newtons: what the behaviours' thresholds compare against.
    pub fn force_magnitude(&self) -> f64 {
        self.force.norm()
    }
}

/// The force-torque sensor at the base of each finger.
pub trait FingerForceTorque: Send + Sync {
    fn wrench(&self, finger: Finger) -> Result<Wrench, HalError>;
}

/// The IR range sensor in the palm, looking along the fingers.
pub trait PalmRange: Send + Sync {
    /// Distance to the nearest surface ahead of the palm, metres; `None` when nothing is within
    /// the sensor's range.
    fn range(&self) -> Result<Option<f64>, HalError>;
}
