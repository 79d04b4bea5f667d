//! The hand's motions the behaviours share: what the hand is made of, and moving it in small
//! steps while watching the finger forces and the palm's range sensor.

use nalgebra::Point3;

use super::force::{FingerForces, ForceRecorder};
use crate::hal::{Arm, Carriage, FingerForceTorque, Gripper, HalError, PalmRange};

/// The hand of an EL-E-like robot: carriage, arm, gripper, finger force-torque, palm IR.
pub trait Hand: Arm + Carriage + Gripper + FingerForceTorque + PalmRange {}

impl<T: Arm + Carriage + Gripper + FingerForceTorque + PalmRange> Hand for T {}

/// The robot's own body, as its maker documents it (a real robot's kinematic description):
/// where the hand is relative to the base, which behaviours need to reach a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotBody {
    /// From the base's centre to the palm with the arm retracted, metres.
    pub palm_ahead: f64,
    /// Length of the fingers beyond the palm, metres.
    pub finger_length: f64,
    /// Where the tilting laser's head is, base frame, metres: planes are seen from there.
    pub laser: Point3<f64>,
}

impl Default for RobotBody {
    /// EL-E-like: the simulator's body.
    fn default() -> Self {
        Self { palm_ahead: 0.25, finger_length: 0.10, laser: Point3::new(0.15, 0.0, 1.0) }
    }
}

/// Arm steps while feeling for contact, metres: small enough that a 2 N threshold is met at a
/// millimetre of compression, not pushed through.
pub const FEEL_STEP: f64 = 0.01;

/// Sets the gripper's opening from the entry's degrees. A gripper that cannot open as wide as
/// the entry asks (an entry written for another robot's hand) opens as far as it goes.
pub fn set_gripper_deg(hand: &impl Hand, degrees: f64, max_force: f64) -> Result<f64, HalError> {
    hand.set_opening(degrees.to_radians().min(hand.widest()), max_force)
}

/// How an advance of the hand ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Touch {
    /// A finger felt more than the threshold.
    Force(FingerForces),
    /// The palm's range sensor saw a surface nearer than the threshold.
    NearRange(f64),
    /// The arm went as far as allowed without touching anything.
    Nothing,
}

impl Touch {
    /// A short account for the task's report.
    pub fn describe(&self) -> String {
        match self {
            Self::Force(f) => format!("touched: {:.1} N and {:.1} N", f.left, f.right),
            Self::NearRange(r) => format!("palm sees a surface {r:.3} m ahead"),
            Self::Nothing => "nothing within reach".to_owned(),
        }
    }
}

/// Extends the arm by up to `reach` metres in [`FEEL_STEP`]s, stopping when a finger feels more
/// than `contact_force` newtons or the palm sees a surface nearer than `near_range` metres, or
/// at the end of the arm's travel. Returns how it ended and how far the arm moved.
pub fn advance_until_touch(
    hand: &impl Hand,
    forces: &mut ForceRecorder<'_>,
    contact_force: f64,
    near_range: Option<f64>,
    reach: f64,
) -> Result<(Touch, f64), HalError> {
    let start = hand.extension()?;
    let reach = reach.min(hand.farthest() - start).max(0.0);
    let mut moved = 0.0;
    while moved < reach - 1e-9 {
        let step = FEEL_STEP.min(reach - moved);
        let reached = hand.move_to_extension(start + moved + step, contact_force)?;
        let felt = forces.sample()?;
        let advanced = reached - (start + moved);
        moved = reached - start;
        if felt.max() > contact_force || advanced < step - 1e-6 {
            return Ok((Touch::Force(felt), moved));
        }
        if let (Some(near), Some(range)) = (near_range, hand.range()?)
            && range < near
        {
            return Ok((Touch::NearRange(range), moved));
        }
    }
    Ok((Touch::Nothing, moved))
}

/// Retracts (or extends) the arm by `by` metres with no force limit that would stop it.
pub fn move_arm_by(hand: &impl Hand, by: f64) -> Result<f64, HalError> {
    let target = (hand.extension()? + by).max(0.0);
    hand.move_to_extension(target, f64::INFINITY)
}
