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
use crate::hal::{HalError, MobileBase, PlanarPose, forward_to};

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

// Every other capability is the wrapped robot's own.
forward_to!([R: TaskRobot] Trailing<'_, R> => robot:
    ColorCamera, BrightnessCamera, TiltingLaser, RfidReader, Carriage, Arm, Gripper,
    FingerForceTorque, PalmRange);
