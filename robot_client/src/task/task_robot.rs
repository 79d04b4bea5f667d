//! What the task needs of a robot: a hand, a base, a camera, a tilting laser, an RFID reader and
//! a camera that measures brightness; any robot with all of them can run it.

use crate::behaviors::Hand;
use crate::hal::{BrightnessCamera, ColorCamera, MobileBase, RfidReader, TiltingLaser};

/// Everything the task needs of a robot.
pub trait TaskRobot:
    Hand + MobileBase + ColorCamera + TiltingLaser + RfidReader + BrightnessCamera
{
}

impl<T: Hand + MobileBase + ColorCamera + TiltingLaser + RfidReader + BrightnessCamera> TaskRobot
    for T
{
}
