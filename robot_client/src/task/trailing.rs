//! The robot as the task drives it toward the tag: every drive and turn of its base adds the
//! pose odometry then reports to the [`Trail`], whichever phase commanded it, so that no
//! motion on the way in is left out of the ground phase 4 may back off over. Everything else
//! passes through untouched.
//!
//! A move in one go ([`MobileBase::move_relative`]) is made as the trait's own turn, drive and
//! turn, each kept: the ground between two poses is known only for a drive straight ahead or a
//! turn in place.

use std::sync::Mutex;

use super::run::TaskRobot;
use super::trail::{Move, Trail};
use crate::hal::{
    Arm, BrightnessCamera, CameraCalibration, Carriage, ColorCamera, ColorImage, Finger,
    FingerForceTorque, GrayImage, Gripper, HalError, LookDirection, MobileBase, PalmRange,
    PlanarPose, PointCloud, RfidReader, TagRead, TiltSweep, TiltingLaser, Wrench,
};

/// `robot`, keeping the trail of its base.
pub(super) struct Trailing<'a, R> {
    robot: &'a R,
    trail: Mutex<Trail>,
}

impl<'a, R: TaskRobot> Trailing<'a, R> {
    /// Starts the trail where the base stands now.
    pub(super) fn new(robot: &'a R) -> Result<Self, HalError> {
        Ok(Self { robot, trail: Mutex::new(Trail::starting_at(robot.pose_estimate()?)) })
    }

    /// The trail so far.
    pub(super) fn trail(&self) -> Trail {
        self.trail.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).clone()
    }

    /// Notes that the tag was seen from where the base stands now.
    pub(super) fn saw_the_tag(&self) -> Result<(), HalError> {
        let height = self.robot.height()?;
        self.trail.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).saw_the_tag(height);
        Ok(())
    }

    /// Adds `made` and where the base stands now, after it moved or failed partway.
    fn keep(&self, made: Move) -> Result<(), HalError> {
        let pose = self.robot.pose_estimate()?;
        self.trail.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push(made, pose);
        Ok(())
    }
}

impl<R: TaskRobot> MobileBase for Trailing<'_, R> {
    fn pose_estimate(&self) -> Result<PlanarPose, HalError> {
        self.robot.pose_estimate()
    }

    fn drive(&self, distance: f64) -> Result<(), HalError> {
        let driven = self.robot.drive(distance);
        self.keep(Move::Drive(distance))?;
        driven
    }

    fn turn(&self, angle: f64) -> Result<(), HalError> {
        let turned = self.robot.turn(angle);
        self.keep(Move::Turn(angle))?;
        turned
    }
}

impl<R: TaskRobot> ColorCamera for Trailing<'_, R> {
    fn calibration(&self) -> CameraCalibration {
        self.robot.calibration()
    }
    fn capture(&self, flash: bool) -> Result<ColorImage, HalError> {
        self.robot.capture(flash)
    }
}

impl<R: TaskRobot> BrightnessCamera for Trailing<'_, R> {
    fn capture_light_source(&self, look: LookDirection) -> Result<GrayImage, HalError> {
        self.robot.capture_light_source(look)
    }
    fn mean_intensity(&self, look: LookDirection) -> Result<f64, HalError> {
        self.robot.mean_intensity(look)
    }
}

impl<R: TaskRobot> TiltingLaser for Trailing<'_, R> {
    fn scan(&self, sweep: &TiltSweep) -> Result<PointCloud, HalError> {
        self.robot.scan(sweep)
    }
}

impl<R: TaskRobot> RfidReader for Trailing<'_, R> {
    fn inventory(&self) -> Result<Vec<TagRead>, HalError> {
        self.robot.inventory()
    }
}

impl<R: TaskRobot> Carriage for Trailing<'_, R> {
    fn height(&self) -> Result<f64, HalError> {
        self.robot.height()
    }
    fn move_to_height(&self, height: f64, max_force: f64) -> Result<f64, HalError> {
        self.robot.move_to_height(height, max_force)
    }
}

impl<R: TaskRobot> Arm for Trailing<'_, R> {
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

impl<R: TaskRobot> Gripper for Trailing<'_, R> {
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

impl<R: TaskRobot> FingerForceTorque for Trailing<'_, R> {
    fn wrench(&self, finger: Finger) -> Result<Wrench, HalError> {
        self.robot.wrench(finger)
    }
}

impl<R: TaskRobot> PalmRange for Trailing<'_, R> {
    fn range(&self) -> Result<Option<f64>, HalError> {
        self.robot.range()
    }
}
