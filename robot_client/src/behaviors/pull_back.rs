//! Pull back (paper §IV-B.2.c): grasp the towel, centring it between the fingers with the
//! force-torque sensors, then back the base off "in steps of 20 cm, stopping when either a force
//! threshold is exceeded (drawer is fully opened), the force on the fingers drops below a
//! threshold (fingers lose their grip), or the robot has moved back farther than a defined
//! distance", re-grasping after each complete step.
//!
//! Success: the hand's displacement while gripping is more than `success_ratio` of the expected
//! `pull_distance` (the learned one when the registry has it). The displacement is recorded as a
//! measurement; the registry learns the median of the successful ones.

use nalgebra::Vector2;
use pps_schema::PullBackParams;

use super::alignment::{AlignmentParams, close_range_alignment};
use super::force::{FingerForces, ForceRecorder};
use super::motion::{Hand, Touch, advance_until_touch, move_arm_by, set_gripper_deg};
use super::{BehaviorReport, Evidence, milli};
use crate::hal::{HalError, MobileBase};

/// How far the base backs off between force checks within a step, metres.
const PULL_INCREMENT: f64 = 0.01;
/// Lateral corrections tried while centring the towel, and the size of each, metres.
const CENTRING_ATTEMPTS: usize = 4;
const CENTRING_STEP: f64 = 0.01;

/// Runs pull back with the entry's parameters.
pub fn pull_back(
    robot: &(impl Hand + MobileBase),
    params: &PullBackParams,
    mut forces: ForceRecorder<'_>,
) -> Result<BehaviorReport, HalError> {
    let mut evidence = Evidence::default();
    let alignment = close_range_alignment(
        robot,
        &mut forces,
        &AlignmentParams::with_backoff(params.alignment_backoff),
        &mut evidence,
    )?;
    evidence.detector("expected_distance", params.pull_distance);
    evidence.detector("success_ratio", params.success_ratio);
    if alignment.contact.is_none() {
        evidence.detector("grasped", false);
        evidence.detector("displacement", 0.0);
        evidence.measure("displacement", 0.0);
        evidence.step("nothing within reach: the towel is not where the tag was seen");
        return Ok(evidence.finish(false, forces));
    }

    // Grasp, centring the towel between the fingers.
    let Some(grip) = grasp(robot, params, &mut forces, &mut evidence, true)? else {
        evidence.detector("grasped", false);
        evidence.detector("displacement", 0.0);
        evidence.measure("displacement", 0.0);
        release(robot, params)?;
        return Ok(evidence.finish(false, forces));
    };
    evidence.detector("grasped", true);
    evidence.step(format!("grasped: {:.1} N and {:.1} N", grip.left, grip.right));

    // Pull back with the base in steps, re-grasping after each complete one.
    let start = robot.pose_estimate()?;
    let mut held_at = start;
    let mut steps = 0;
    let stop = 'pulling: loop {
        let mut in_step = 0.0;
        while in_step < params.step - 1e-9 {
            let increment = PULL_INCREMENT.min(params.step - in_step);
            robot.drive(-increment)?;
            in_step += increment;
            let felt = forces.sample()?;
            let pose = robot.pose_estimate()?;
            if felt.max() > params.stop_force {
                held_at = pose;
                break 'pulling "stop_force";
            }
            if felt.min() < params.lost_grip_force {
                break 'pulling "lost_grip";
            }
            held_at = pose;
            if (held_at.translation.vector - start.translation.vector).norm()
                >= params.pull_distance
            {
                break 'pulling "distance";
            }
        }
        steps += 1;
        if grasp(robot, params, &mut forces, &mut evidence, false)?.is_none() {
            break 'pulling "lost_grip";
        }
    };
    let displacement = (held_at.translation.vector - start.translation.vector).norm();
    release(robot, params)?;

    let success = displacement > params.success_ratio * params.pull_distance;
    evidence.detector("displacement", milli(displacement));
    evidence.detector("stopped_by", stop);
    evidence.measure("displacement", milli(displacement));
    evidence.measure("steps", steps);
    evidence.step(format!(
        "pulled back {:.3} m in {} step(s), stopped by {stop}; expected {:.3} m",
        displacement, steps, params.pull_distance
    ));
    Ok(evidence.finish(success, forces))
}

/// Closes on the towel until both fingers feel `grasp_force`; when only one does, the towel is
/// off-centre toward it, so the hand opens, moves that way and closes again. `reach` first
/// moves the open hand forward onto the towel. `None` when no grasp was made.
fn grasp(
    robot: &(impl Hand + MobileBase),
    params: &PullBackParams,
    forces: &mut ForceRecorder<'_>,
    evidence: &mut Evidence,
    reach: bool,
) -> Result<Option<FingerForces>, HalError> {
    if reach {
        set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
        let (touch, moved) = advance_until_touch(
            robot,
            forces,
            params.grasp_force,
            Some(AlignmentParams::NEAR_RANGE),
            AlignmentParams::MAX_REACH,
        )?;
        evidence.step(format!(
            "opened to {}°, moved onto the towel {:.3} m ({})",
            params.gripper_deg,
            moved,
            touch.describe()
        ));
        if touch == Touch::Nothing {
            return Ok(None);
        }
    }
    for attempt in 0..=CENTRING_ATTEMPTS {
        robot.set_opening(0.0, params.grasp_force * 2.0)?;
        let felt = forces.sample()?;
        if felt.min() > params.grasp_force {
            return Ok(Some(felt));
        }
        if felt.max() <= params.grasp_force || attempt == CENTRING_ATTEMPTS {
            evidence.step(format!("no grasp: {:.1} N and {:.1} N", felt.left, felt.right));
            return Ok(None);
        }
        // Left is +y: move toward the finger that touched first.
        let toward = if felt.left > felt.right { 1.0 } else { -1.0 };
        set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
        robot.move_relative(Vector2::new(0.0, toward * CENTRING_STEP), 0.0)?;
        evidence.step(format!(
            "centring: {:.1} N left, {:.1} N right, moved {:+.3} m sideways",
            felt.left,
            felt.right,
            toward * CENTRING_STEP
        ));
    }
    Ok(None)
}

fn release(robot: &impl Hand, params: &PullBackParams) -> Result<(), HalError> {
    set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
    move_arm_by(robot, -params.alignment_backoff)?;
    Ok(())
}
