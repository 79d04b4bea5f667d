//! Push (paper §IV-B.2.d): "EL-E first sets its gripper to the settings specified in the
//! semantic database. ... Next, EL-E moves its end-effector forward stopping if a force greater
//! than 2 N is detected or the IR sensor in the palm reports an obstruction. Having made
//! contact, or coming close to it, EL-E then pushes forward with its base for the requested
//! distance or until a force threshold is exceeded."
//!
//! Success, as the entry's `change` says: `location` — the base pushed at least
//! `success_ratio` of `push_distance`; `overall_brightness` — the light changed as asked.

use pps_schema::{PushParams, StateChange};

use super::alignment::{AlignmentParams, close_range_alignment};
use super::force::ForceRecorder;
use super::light_check::light_changed_as_wanted;
use super::motion::{Hand, Touch, advance_until_touch, move_arm_by, set_gripper_deg};
use super::{BehaviorReport, Evidence, WantedLight, milli};
use crate::hal::{BrightnessCamera, HalError, LookDirection, MobileBase};

/// How far the base pushes between force checks, metres.
const PUSH_INCREMENT: f64 = 0.02;

/// Runs push with the entry's parameters; `change` and `look` come from the entry's properties.
pub fn push(
    robot: &(impl Hand + MobileBase + BrightnessCamera),
    params: &PushParams,
    change: StateChange,
    look: LookDirection,
    wanted: WantedLight,
    mut forces: ForceRecorder<'_>,
) -> Result<BehaviorReport, HalError> {
    let mut evidence = Evidence::default();
    let by_brightness = change == StateChange::OverallBrightness;
    let before = if by_brightness { Some(robot.mean_intensity(look)?) } else { None };

    close_range_alignment(
        robot,
        &mut forces,
        &AlignmentParams {
            contact_force: params.contact_force,
            ..AlignmentParams::with_backoff(params.alignment_backoff)
        },
        &mut evidence,
    )?;

    // The gripper as the entry says: open for a drawer front, closed to poke a switch.
    set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
    let (touch, _) = advance_until_touch(
        robot,
        &mut forces,
        params.contact_force,
        Some(AlignmentParams::NEAR_RANGE),
        AlignmentParams::MAX_REACH,
    )?;
    let touched = touch != Touch::Nothing;
    evidence.step(format!(
        "gripper at {}°, forward to the surface: {}",
        params.gripper_deg,
        touch.describe()
    ));

    // Push with the base for the distance, or until the force threshold.
    let start = robot.pose_estimate()?;
    let mut pushed = 0.0;
    let mut stopped_by = "distance";
    if touched {
        while pushed < params.push_distance - 1e-9 {
            let increment = PUSH_INCREMENT.min(params.push_distance - pushed);
            robot.drive(increment)?;
            let felt = forces.sample()?;
            let pose = robot.pose_estimate()?;
            pushed = (pose.translation.vector - start.translation.vector).norm();
            if felt.max() > params.stop_force {
                // The last increment went into something that did not give: take it back.
                robot.drive(-increment)?;
                pushed = (pushed - increment).max(0.0);
                stopped_by = "stop_force";
                break;
            }
        }
    } else {
        stopped_by = "no_contact";
    }
    move_arm_by(robot, -params.alignment_backoff)?;
    evidence.measure("pushed", milli(pushed));
    evidence.detector("pushed", milli(pushed));
    evidence.detector("stopped_by", stopped_by);
    evidence.step(format!("pushed {:.3} m with the base, stopped by {stopped_by}", pushed));

    let success = match before {
        Some(before) => {
            let after = robot.mean_intensity(look)?;
            light_changed_as_wanted(
                before,
                after,
                params.brightness_threshold,
                wanted,
                &mut evidence,
            )
        }
        None => {
            evidence.detector("change", "location");
            evidence.detector("expected_distance", params.push_distance);
            evidence.detector("success_ratio", params.success_ratio);
            touched && pushed >= params.success_ratio * params.push_distance
        }
    };
    Ok(evidence.finish(success, forces))
}
