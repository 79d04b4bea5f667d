//! The robot as the task drives it toward the tag: every drive and turn of its base, every lift
//! of its carriage and reach of its arm adds where the robot then stands to the [`Trail`],
//! whichever phase made it, so that no motion on the way in is left out of what phase 4 may
//! back off over. A drive or turn is kept as it was made ([`as_made`]): one its base stopped
//! partway is kept as far as it went. Everything else passes through untouched.
//!
//! A move in one go ([`MobileBase::move_relative`]) is made as the trait's own turn, drive and
//! turn, each kept: the ground between two poses is known only for a drive straight ahead or a
//! turn in place.

use std::sync::Mutex;

use super::as_made::as_made;
use super::outline::Stance;
use super::task_robot::TaskRobot;
use super::trail::{Move, Trail};
use crate::hal::{Arm, Carriage, HalError, MobileBase, PlanarPose, forward_to};

/// `robot`, keeping the trail of its base.
pub(super) struct Trailing<'a, R> {
    robot: &'a R,
    trail: Mutex<Trail>,
}

impl<'a, R: TaskRobot> Trailing<'a, R> {
    /// Starts the trail where the robot stands now.
    pub(super) fn new(robot: &'a R) -> Result<Self, HalError> {
        let stance = stance(robot)?;
        Ok(Self { robot, trail: Mutex::new(Trail::starting_at(stance)) })
    }

    /// The trail so far.
    pub(super) fn trail(&self) -> Trail {
        self.trail.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).clone()
    }

    /// Notes that the tag was seen from where the robot stands now.
    pub(super) fn saw_the_tag(&self) {
        self.trail.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).saw_the_tag();
    }

    /// Adds `made` and where the robot stands now, after it moved or failed partway.
    fn keep(&self, made: Move) -> Result<(), HalError> {
        let stance = stance(self.robot)?;
        self.trail.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push(made, stance);
        Ok(())
    }

    /// Makes a drive or turn with `make` from `before` (odometry), keeping it as it was made.
    fn keep_base_move(
        &self,
        commanded: Move,
        make: impl FnOnce() -> Result<(), HalError>,
    ) -> Result<(), HalError> {
        let before = self.robot.pose_estimate()?;
        let made = make();
        let after: PlanarPose = self.robot.pose_estimate()?;
        self.keep(as_made(commanded, &before, &after))?;
        made
    }
}

/// Where `robot`'s base, carriage and arm are now.
fn stance(robot: &impl TaskRobot) -> Result<Stance, HalError> {
    Ok(Stance {
        base: robot.pose_estimate()?,
        height: robot.height()?,
        extension: robot.extension()?,
    })
}

impl<R: TaskRobot> MobileBase for Trailing<'_, R> {
    fn pose_estimate(&self) -> Result<PlanarPose, HalError> {
        self.robot.pose_estimate()
    }

    fn drive(&self, distance: f64) -> Result<(), HalError> {
        self.keep_base_move(Move::Drive(distance), || self.robot.drive(distance))
    }

    fn turn(&self, angle: f64) -> Result<(), HalError> {
        self.keep_base_move(Move::Turn(angle), || self.robot.turn(angle))
    }
}

impl<R: TaskRobot> Carriage for Trailing<'_, R> {
    fn height(&self) -> Result<f64, HalError> {
        self.robot.height()
    }

    fn move_to_height(&self, height: f64, max_force: f64) -> Result<f64, HalError> {
        let from = self.robot.height()?;
        let moved = self.robot.move_to_height(height, max_force);
        let to = self.robot.height()?;
        self.keep(Move::Lift { from, to })?;
        moved
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
        let from = self.robot.extension()?;
        let moved = self.robot.move_to_extension(extension, max_force);
        let to = self.robot.extension()?;
        self.keep(Move::Reach { from, to })?;
        moved
    }
}

// Every other capability is the wrapped robot's own.
forward_to!([R: TaskRobot] Trailing<'_, R> => robot:
    ColorCamera, BrightnessCamera, TiltingLaser, RfidReader, Gripper, FingerForceTorque,
    PalmRange);
