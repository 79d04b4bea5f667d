//! Pull lamp (paper §IV-B.2.e): "EL-E has only moved back 8 cm after contact to place the
//! PPS-tag in the forward part of its gripper. EL-E then closes its gripper, stopping when a
//! threshold force has been reached. After gripping the pull chain, EL-E uses the same carriage
//! control as in the light switch operation to apply a downward force directly on the lamp's
//! chain, stopping when EL-E's fingers either detect a force greater than 10 N or have moved
//! down more than 7 cm." The brightness camera looks forward, at the lamp.

use pps_schema::PullLampParams;

use super::alignment::{AlignmentParams, close_range_alignment};
use super::force::ForceRecorder;
use super::light_check::light_changed_as_wanted;
use super::motion::{Hand, move_arm_by, set_gripper_deg};
use super::{BehaviorReport, Evidence, WantedLight, milli};
use crate::hal::{BrightnessCamera, HalError, LookDirection};

/// Re-grasps after closing on nothing, and how much further each reaches, metres.
const REGRASPS: usize = 3;
const REGRASP_STEP: f64 = 0.01;

/// Runs pull lamp with the entry's parameters.
pub fn pull_lamp(
    robot: &(impl Hand + BrightnessCamera),
    params: &PullLampParams,
    look: LookDirection,
    wanted: WantedLight,
    mut forces: ForceRecorder<'_>,
) -> Result<BehaviorReport, HalError> {
    let mut evidence = Evidence::default();
    let before = robot.mean_intensity(look)?;

    // Open to the entry's angle so the chain can come between the fingers, then align: the
    // palm's range sensor finds the foam, and the short back-off leaves it at the fingers' front.
    set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
    close_range_alignment(
        robot,
        &mut forces,
        &AlignmentParams::with_backoff(params.alignment_backoff),
        &mut evidence,
    )?;

    // Close on the chain until the grip force. Closing on nothing means the foam is still
    // beyond the fingertips (the palm saw it a little early): open, reach a centimetre further,
    // and close again.
    robot.set_opening(0.0, params.grip_force)?;
    let mut grip = forces.sample()?;
    for _ in 0..REGRASPS {
        if grip.min() >= params.grip_force / 2.0 {
            break;
        }
        set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
        move_arm_by(robot, REGRASP_STEP)?;
        robot.set_opening(0.0, params.grip_force)?;
        grip = forces.sample()?;
        evidence
            .step(format!("closed on nothing; reached {REGRASP_STEP} m further and closed again"));
    }
    evidence.detector("grip_force", milli(grip.min()));
    evidence.step(format!("closed on the chain: {:.1} N", grip.max()));

    // Pull down with the carriage until the force or the distance.
    let from = robot.height()?;
    let reached = robot.move_to_height(from - params.max_pull_distance, params.max_pull_force)?;
    let felt = forces.sample()?;
    let pulled = from - reached;
    evidence.measure("pulled", milli(pulled));
    evidence.step(format!("pulled down {:.3} m (stopped at {:.1} N)", pulled, felt.max()));

    // Let go and step back before looking at the lamp.
    set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
    robot.move_to_height(from, f64::INFINITY)?;
    move_arm_by(robot, -params.alignment_backoff)?;

    let after = robot.mean_intensity(look)?;
    let success =
        light_changed_as_wanted(before, after, params.brightness_threshold, wanted, &mut evidence);
    Ok(evidence.finish(success, forces))
}
