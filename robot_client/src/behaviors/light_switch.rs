//! Light switch (paper §IV-B.2.b): "EL-E moves the carriage up (or down depending on the
//! command), closes the gripper (but not all the way), moves the gripper forward until contact
//! has been made with the wall (using a 2 N threshold), moves the gripper away from the wall by
//! 2 cm (to clear the plate on which the light switch is mounted), then moves the carriage down
//! (or up) using torque control with the gripper extended, and stops when the maximum force on
//! EL-E's gripper is greater than 12 N or has traveled 15 cm." A rocker (the ADA switch of the
//! paper's Fig. 4) is pressed instead: forward at `height_offset` until `force_threshold`.
//!
//! Success: the mean brightness where the light is expected, before minus after; its sign says
//! on or off, and it must match what was asked.

use pps_schema::{LightSwitchParams, SweepDirection, SwitchMotion};

use super::alignment::{AlignmentParams, close_range_alignment};
use super::force::ForceRecorder;
use super::light_check::light_changed_as_wanted;
use super::motion::{Hand, Touch, advance_until_touch, move_arm_by, set_gripper_deg};
use super::{BehaviorReport, Evidence, WantedLight, milli};
use crate::hal::{BrightnessCamera, HalError, LookDirection};

/// Runs the light switch behaviour with the entry's parameters.
pub fn operate_light_switch(
    robot: &(impl Hand + BrightnessCamera),
    params: &LightSwitchParams,
    look: LookDirection,
    wanted: WantedLight,
    mut forces: ForceRecorder<'_>,
) -> Result<BehaviorReport, HalError> {
    let mut evidence = Evidence::default();
    let before = robot.mean_intensity(look)?;

    // Close-range alignment against the tag, backing off the entry's distance.
    let alignment = close_range_alignment(
        robot,
        &mut forces,
        &AlignmentParams {
            contact_force: params.contact_force,
            ..AlignmentParams::with_backoff(params.alignment_backoff)
        },
        &mut evidence,
    )?;
    if alignment.contact.is_none() {
        evidence.detector("contact", false);
        evidence.step("nothing within reach: the switch is not where the tag was seen");
        return Ok(evidence.finish(false, forces));
    }

    // Carriage up (or down) by the entry's offset from the tag's centre.
    let start_height = robot.height()?;
    robot.move_to_height(start_height + params.height_offset, params.max_carriage_force)?;
    // Close the gripper, but not all the way.
    set_gripper_deg(robot, params.gripper_deg, params.max_carriage_force)?;
    evidence.step(format!(
        "carriage {:+.3} m, gripper at {}°",
        params.height_offset, params.gripper_deg
    ));

    let travel = match params.motion {
        SwitchMotion::Flip => flip(robot, params, &mut forces, &mut evidence)?,
        SwitchMotion::Press => press(robot, params, &mut forces, &mut evidence)?,
    };

    // Hands off the switch before looking, so the after-picture sees only the light.
    move_arm_by(robot, -params.alignment_backoff)?;
    robot.move_to_height(start_height, f64::INFINITY)?;
    let after = robot.mean_intensity(look)?;
    let success =
        light_changed_as_wanted(before, after, params.brightness_threshold, wanted, &mut evidence);
    evidence.measure("carriage_travel", milli(travel));
    Ok(evidence.finish(success, forces))
}

/// Flip: to the wall, back off the plate, sweep the toggle with the carriage.
fn flip(
    robot: &impl Hand,
    params: &LightSwitchParams,
    forces: &mut ForceRecorder<'_>,
    evidence: &mut Evidence,
) -> Result<f64, HalError> {
    let (touch, _) =
        advance_until_touch(robot, forces, params.contact_force, None, AlignmentParams::MAX_REACH)?;
    if !matches!(touch, Touch::Force(_)) {
        evidence.step("no wall within reach");
        return Ok(0.0);
    }
    move_arm_by(robot, -params.wall_clearance)?;
    let from = robot.height()?;
    let sign = match params.direction {
        Some(SweepDirection::Down) => -1.0,
        _ => 1.0,
    };
    let reached =
        robot.move_to_height(from + sign * params.max_travel, params.max_carriage_force)?;
    let felt = forces.sample()?;
    evidence.step(format!(
        "touched the wall, {} m clear, swept the carriage {:+.3} m (stopped at {:.1} N)",
        params.wall_clearance,
        reached - from,
        felt.max()
    ));
    Ok((reached - from).abs())
}

/// Press: push along the wall's normal at the offset until the force threshold.
fn press(
    robot: &impl Hand,
    params: &LightSwitchParams,
    forces: &mut ForceRecorder<'_>,
    evidence: &mut Evidence,
) -> Result<f64, HalError> {
    let (touch, moved) = advance_until_touch(
        robot,
        forces,
        params.force_threshold,
        None,
        AlignmentParams::MAX_REACH,
    )?;
    let pressed = matches!(touch, Touch::Force(_));
    evidence.step(if pressed {
        format!("pressed to {} N after {:.3} m", params.force_threshold, moved)
    } else {
        "nothing to press within reach".to_owned()
    });
    move_arm_by(robot, -moved.min(0.03))?;
    Ok(moved)
}
