//! The simulated robot with a real RFID reader in its fingers: every capability is the
//! simulator's except [`RfidReader`], so `pps-robot run --rfid-llrp` reads real tags in phase 3.

use crate::hal::{HalError, RfidReader, TagRead, forward_to};
use crate::sim::SimRobot;

pub struct WithRealReader<'a> {
    pub robot: SimRobot,
    pub reader: &'a dyn RfidReader,
}

impl std::fmt::Debug for WithRealReader<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WithRealReader").field("robot", &self.robot).finish_non_exhaustive()
    }
}

impl RfidReader for WithRealReader<'_> {
    fn inventory(&self) -> Result<Vec<TagRead>, HalError> {
        self.reader.inventory()
    }
}

// Every other capability is the simulator's.
forward_to!([] WithRealReader<'_> => robot:
    ColorCamera, BrightnessCamera, TiltingLaser, MobileBase, Carriage, Arm, Gripper,
    FingerForceTorque, PalmRange);
