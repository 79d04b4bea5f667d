//! The simulated robot with a real RFID reader in its fingers: every capability is the
//! simulator's except [`RfidReader`], so `pps-robot run --rfid-llrp` reads real tags in phase 3.

use nalgebra::Vector2;

use crate::hal::{
    Arm, BrightnessCamera, CameraCalibration, Carriage, ColorCamera, ColorImage, Finger,
    FingerForceTorque, GrayImage, Gripper, HalError, LookDirection, MobileBase, PalmRange,
    PlanarPose, PointCloud, RfidReader, TagRead, TiltSweep, TiltingLaser, Wrench,
};
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

impl ColorCamera for WithRealReader<'_> {
    fn calibration(&self) -> CameraCalibration {
        self.robot.calibration()
    }
    fn capture(&self, flash: bool) -> Result<ColorImage, HalError> {
        self.robot.capture(flash)
    }
}

impl BrightnessCamera for WithRealReader<'_> {
    fn capture_light_source(&self, look: LookDirection) -> Result<GrayImage, HalError> {
        self.robot.capture_light_source(look)
    }
    fn mean_intensity(&self, look: LookDirection) -> Result<f64, HalError> {
        self.robot.mean_intensity(look)
    }
}

impl TiltingLaser for WithRealReader<'_> {
    fn scan(&self, sweep: &TiltSweep) -> Result<PointCloud, HalError> {
        self.robot.scan(sweep)
    }
}

impl MobileBase for WithRealReader<'_> {
    fn pose_estimate(&self) -> Result<PlanarPose, HalError> {
        self.robot.pose_estimate()
    }
    fn drive(&self, distance: f64) -> Result<(), HalError> {
        self.robot.drive(distance)
    }
    fn turn(&self, angle: f64) -> Result<(), HalError> {
        self.robot.turn(angle)
    }
    fn move_relative(&self, translation: Vector2<f64>, yaw: f64) -> Result<(), HalError> {
        self.robot.move_relative(translation, yaw)
    }
}

impl Carriage for WithRealReader<'_> {
    fn height(&self) -> Result<f64, HalError> {
        self.robot.height()
    }
    fn move_to_height(&self, height: f64, max_force: f64) -> Result<f64, HalError> {
        self.robot.move_to_height(height, max_force)
    }
}

impl Arm for WithRealReader<'_> {
    fn extension(&self) -> Result<f64, HalError> {
        self.robot.extension()
    }
    fn farthest(&self) -> f64 {
        self.robot.farthest()
    }
    fn move_to_extension(&self, extension: f64, max_force: f64) -> Result<f64, HalError> {
        self.robot.move_to_extension(extension, max_force)
    }
}

impl Gripper for WithRealReader<'_> {
    fn opening(&self) -> Result<f64, HalError> {
        self.robot.opening()
    }
    fn widest(&self) -> f64 {
        self.robot.widest()
    }
    fn set_opening(&self, angle: f64, max_force: f64) -> Result<f64, HalError> {
        self.robot.set_opening(angle, max_force)
    }
}

impl FingerForceTorque for WithRealReader<'_> {
    fn wrench(&self, finger: Finger) -> Result<Wrench, HalError> {
        self.robot.wrench(finger)
    }
}

impl PalmRange for WithRealReader<'_> {
    fn range(&self) -> Result<Option<f64>, HalError> {
        self.robot.range()
    }
}
