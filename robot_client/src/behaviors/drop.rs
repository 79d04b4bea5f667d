//! Drop (paper §IV-B.2.f): "EL-E first uses its tilting laser range finder to scan the
//! container, segment out all planes in a cylindrical volume around the PPS-tag, select the
//! closest plane to the PPS-tag, calculate the orientation of the plane, and find a point above
//! the container from which to drop the object. After this, EL-E drives towards the container
//! stopping 45 cm from the drop location, moves its end effector to the location, and releases
//! the object." No close-range alignment: the held object blocks the hand.
//!
//! Success: nothing felt in the hand afterwards, by the finger forces and the palm's range.

use nalgebra::{Point3, Vector2};
use pps_schema::DropParams;

use super::force::ForceRecorder;
use super::motion::{Hand, RobotBody, move_arm_by, set_gripper_deg};
use super::{BehaviorReport, Evidence, milli};
use crate::hal::{HalError, MobileBase, TiltSweep, TiltingLaser};
use crate::navigation::find_container_opening;

/// What the drop needs besides the entry: where the tag was seen and how to scan for the
/// container.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DropGeometry {
    /// The tag's centre, base frame, metres.
    pub tag: Point3<f64>,
    /// A sweep that sees the container's top from where the robot stands.
    pub sweep: TiltSweep,
    pub body: RobotBody,
    /// Seed of the plane search.
    pub seed: u64,
}

/// Runs drop with the entry's parameters.
pub fn drop_object(
    robot: &(impl Hand + MobileBase + TiltingLaser),
    params: &DropParams,
    geometry: &DropGeometry,
    mut forces: ForceRecorder<'_>,
) -> Result<BehaviorReport, HalError> {
    let mut evidence = Evidence::default();
    let held_before = forces.sample()?;
    evidence.detector("force_before", milli(held_before.max()));

    // Scan, and find the container's front and a point over its opening.
    let cloud = robot.scan(&geometry.sweep)?;
    let search =
        find_container_opening(&cloud.points, &geometry.tag, &geometry.body.laser, geometry.seed);
    let Some(opening) = search.opening else {
        evidence.detector("container_found", false);
        evidence.step(format!("no container front among {} planes", search.planes));
        return Ok(evidence.finish(false, forces));
    };
    let drop_point = opening.drop_point;
    evidence.detector("container_found", true);
    evidence.measure("rim_height", milli(drop_point.z));
    evidence.step(format!(
        "scanned {} points, {} planes; drop point {:.2} m ahead, rim at {:.2} m",
        search.points, search.planes, drop_point.x, drop_point.z
    ));

    // Hand up above the rim and in, then drive to the standoff, facing the drop point.
    robot.move_to_height(drop_point.z + params.release_height, f64::INFINITY)?;
    robot.move_to_extension(0.0, f64::INFINITY)?;
    let flat = Vector2::new(drop_point.x, drop_point.y);
    let heading = flat.y.atan2(flat.x);
    robot.turn(heading)?;
    let approach = flat.norm() - params.standoff;
    robot.drive(approach)?;
    // Reach out over the opening.
    let reach = params.standoff - geometry.body.palm_ahead - geometry.body.finger_length / 2.0;
    robot.move_to_extension(reach.max(0.0), f64::INFINITY)?;
    evidence.step(format!(
        "drove {:.2} m to {} m from the drop point, hand {} m above the rim",
        approach, params.standoff, params.release_height
    ));

    // Release.
    set_gripper_deg(robot, params.gripper_deg, f64::INFINITY)?;
    let felt = forces.sample()?;
    let range = robot.range()?;
    move_arm_by(robot, -reach.max(0.0))?;
    let by_force = felt.max() > params.still_held_force;
    let by_range = range.is_some_and(|r| r < params.still_held_range);
    let still_held = by_force || by_range;
    evidence.detector("force_after", milli(felt.max()));
    evidence.detector("palm_range_after", range.map(milli));
    evidence.detector("still_held", still_held);
    evidence.step(format!(
        "opened to {}°: {:.2} N in the fingers, palm range {}",
        params.gripper_deg,
        felt.max(),
        range.map_or("clear".to_owned(), |r| format!("{r:.3} m"))
    ));
    Ok(evidence.finish(!still_held, forces))
}
