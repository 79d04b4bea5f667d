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
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::force::ForceRecorder;
use super::motion::{Hand, RobotBody, move_arm_by, set_gripper_deg};
use super::{BehaviorReport, Evidence, milli};
use crate::hal::{HalError, MobileBase, TiltSweep, TiltingLaser};
use crate::navigation::{
    BackingPlaneRule, PlaneSearchParams, VolumeOfInterest, choose_backing_plane, find_planes,
};

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

    // Scan, find the planes around the tag, and the container's front among them.
    let cloud = robot.scan(&geometry.sweep)?;
    let voi = VolumeOfInterest::around(geometry.tag, 0.4, 0.5);
    let points = voi.crop(&cloud.points);
    let sensor = geometry.body.laser;
    let mut rng = ChaCha8Rng::seed_from_u64(geometry.seed);
    let planes = find_planes(&points, &sensor, &PlaneSearchParams::default(), &mut rng).planes;
    // The tag on a trash can is a patch: 5 cm of reach is plenty for the foot-gap rule.
    let Some(front) = choose_backing_plane(
        &planes,
        &points,
        &geometry.tag,
        0.05,
        &[],
        &sensor,
        &BackingPlaneRule::default(),
    )
    .plane
    else {
        evidence.detector("container_found", false);
        evidence.step(format!("no container front among {} planes", planes.len()));
        return Ok(evidence.finish(false, forces));
    };
    // The opening: the level surface behind the front and above the tag, nearest the tag (the
    // container's top, not the floor below it or a table beyond it).
    let top = planes
        .iter()
        .filter(|p| p.plane.normal.z.abs() > 20f64.to_radians().cos())
        .filter(|p| p.centroid.z > geometry.tag.z)
        .filter(|p| front.normal.dot(&p.centroid.coords) + front.offset < 0.0)
        .min_by(|a, b| {
            let d = |p: &&crate::navigation::DetectedPlane| (p.centroid - geometry.tag).norm();
            d(a).total_cmp(&d(b))
        });
    let drop_point = match top {
        Some(top) => top.centroid,
        // No top seen: a hand's width behind the front, at the tag's height.
        None => geometry.tag - front.normal * 0.1,
    };
    evidence.detector("container_found", true);
    evidence.measure("rim_height", milli(drop_point.z));
    evidence.step(format!(
        "scanned {} points, {} planes; drop point {:.2} m ahead, rim at {:.2} m",
        points.len(),
        planes.len(),
        drop_point.x,
        drop_point.z
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
