//! Phase 2 (paper §IV-B.1.a): with the camera and the tilting laser, find the tag nearest the
//! pointed location and the surface behind it, and drive to the waypoint 50 cm out along the
//! surface's normal, facing the tag ([`plan_approach`] does the geometry).

use nalgebra::{Point3, Vector2};

use super::drive::{in_base, in_odom};
use super::report::PhaseReport;
use crate::hal::{ColorCamera, HalError, MobileBase, TiltSweep, TiltingLaser};
use crate::navigation::{ApproachParams, ApproachPlan, Clearance, plan_approach};

/// Perceives around `target` (odometry frame) from where the robot stands.
pub(crate) fn perceive(
    robot: &(impl ColorCamera + TiltingLaser + MobileBase),
    target: &Point3<f64>,
    sweep: &TiltSweep,
    params: &ApproachParams,
) -> Result<ApproachPlan, HalError> {
    let target = in_base(robot, target)?;
    let image = robot.capture(true)?;
    let cloud = robot.scan(sweep)?;
    plan_approach(&image, &cloud, &robot.calibration(), &target, params)
        .map_err(|e| HalError::Failed { device: "camera", reason: e.to_string() })
}

/// Finds the tag and drives to its waypoint; returns the tag's centre in the odometry frame,
/// or `None` (with the reason in the report) when there is no way to approach it.
pub(crate) fn approach_tag(
    robot: &(impl ColorCamera + TiltingLaser + MobileBase),
    target: &Point3<f64>,
    sweep: &TiltSweep,
    params: &ApproachParams,
    report: &mut PhaseReport,
) -> Result<Option<Point3<f64>>, HalError> {
    let mut plan = perceive(robot, target, sweep, params)?;
    if plan.tag.is_none() {
        // Too close to see it whole, or at the image's edge: step back once and look again.
        robot.drive(-0.25)?;
        report.note("no tag near the pointed location; backed off 0.25 m to look again");
        plan = perceive(robot, target, sweep, params)?;
    } else if plan.backing_plane.is_none() {
        // A sparse scan of an oblique surface: one more look usually finds it.
        report
            .note(format!("no surface behind the tag among {} planes; looking again", plan.planes));
        let again = ApproachParams { seed: params.seed.wrapping_add(1), ..params.clone() };
        plan = perceive(robot, target, sweep, &again)?;
    }
    let Some(sighting) = &plan.tag else {
        report.fail("no red tag near the pointed location");
        return Ok(None);
    };
    let tag = sighting.nearest();
    report.note(format!(
        "tag: {} laser points, {:.2} m from the pointed location{}",
        tag.points,
        tag.distance_to_target,
        if sighting.is_ambiguous() { " (another tag about as near)" } else { "" }
    ));
    let (Some(plane), Some(waypoint)) = (&plan.backing_plane, &plan.waypoint) else {
        report.fail(format!("no surface behind the tag among {} planes", plan.planes));
        return Ok(None);
    };
    report.note(format!(
        "backing plane: {} points, {} planes in the volume of interest",
        plane.points, plan.planes
    ));
    if let Some(Clearance::Blocked { points, .. }) = plan.clearance {
        report
            .fail(format!("the waypoint is blocked ({points} points inside the robot's outline)"));
        return Ok(None);
    }
    let tag_odom = in_odom(robot, &tag.centroid)?;
    let w = waypoint.position;
    robot.move_relative(Vector2::new(w.x, w.y), waypoint.yaw)?;
    report.note(format!(
        "drove to the waypoint {:.2} m away, {:.0}° off the way it faced, and turned to the tag",
        w.x.hypot(w.y),
        w.y.atan2(w.x).to_degrees()
    ));
    Ok(Some(tag_odom))
}
