//! Phase 2 (paper §IV-B.1.a): with the camera and the tilting laser, find the tag nearest the
//! pointed location and the surface behind it, and drive to the waypoint 50 cm out along the
//! surface's normal, facing the tag ([`plan_approach`] does the geometry).

use nalgebra::{Point3, Vector2};

use super::drive::{in_base, in_odom};
use super::report::PhaseReport;
use crate::hal::{
    ColorCamera, ColorImage, HalError, MobileBase, Operator, TiltSweep, TiltingLaser,
};
use crate::navigation::{ApproachParams, ApproachPlan, Clearance, RejectedPlane, plan_approach};

/// One look from where the robot stands: the flash image and what perception made of it.
pub(crate) struct Look {
    pub image: ColorImage,
    pub plan: ApproachPlan,
    /// The point looked around (odometry frame): where the person pointed.
    pub target: Point3<f64>,
}

/// Perceives around `target` (odometry frame) from where the robot stands, keeping the image
/// looked at.
pub(crate) fn look(
    robot: &(impl ColorCamera + TiltingLaser + MobileBase),
    target: &Point3<f64>,
    sweep: &TiltSweep,
    params: &ApproachParams,
) -> Result<Look, HalError> {
    let here = in_base(robot, target)?;
    let image = robot.capture(true)?;
    let cloud = robot.scan(sweep)?;
    let plan = plan_approach(&image, &cloud, &robot.calibration(), &here, params)
        .map_err(|e| HalError::Failed { device: "camera", reason: e.to_string() })?;
    Ok(Look { image, plan, target: *target })
}

/// What a caretaker can do when the red thing nearest the pointed location was too large to
/// be a tag and the tag could not be told from it. With every tag's size known, a size is no
/// help: only the red thing or the pointing can change.
fn too_large_advice(sized: bool) -> &'static str {
    if sized {
        "something red larger than any tag of this home is where you pointed, and the tag could \
         not be told apart from it; move the red thing away from the tag, or point at the \
         middle of the tag"
    } else {
        "something red larger than any tag of this home is where you pointed, and the tag could \
         not be told apart from it; move the red thing away from the tag, or give the tag's \
         size in its form"
    }
}

/// Perceives around `target` until a look finds the tag and the surface behind it; returns the
/// last look, which [`drive_to_waypoint`] follows.
///
/// When a look finds the tag but no surface behind it, the robot first looks again from a
/// better place (square to the surface it half saw, or further back), as the paper's person
/// would otherwise be asked to point again; only when that look fails too is the person asked.
pub(crate) fn look_for_tag_and_surface(
    robot: &(impl ColorCamera + TiltingLaser + MobileBase),
    operator: &dyn Operator,
    target: &Point3<f64>,
    sweep: &TiltSweep,
    params: &ApproachParams,
    report: &mut PhaseReport,
) -> Result<Look, HalError> {
    let mut target = *target;
    let mut seen = look(robot, &target, sweep, params)?;
    if seen.plan.tag.is_none() {
        // Too close to see it whole, or at the image's edge: step back once and look again.
        robot.drive(-0.25)?;
        report.note("no tag near the pointed location; backed off 0.25 m to look again");
        seen = look(robot, &target, sweep, params)?;
    }
    if seen.plan.tag.is_some() && seen.plan.backing_plane.is_none() {
        report.note(format!(
            "no surface behind the tag among {} planes ({})",
            seen.plan.planes.len(),
            nearest_rejection(&seen.plan)
        ));
        let moved = step_to_a_better_view(robot, &seen.plan, report)?;
        let again = ApproachParams { seed: params.seed.wrapping_add(1), ..params.clone() };
        seen = look(robot, &target, sweep, &again)?;
        if seen.plan.backing_plane.is_none() {
            report.note(format!(
                "still no surface behind the tag {}; asking the person to point again",
                if moved { "from there" } else { "on a second look" }
            ));
            match operator.pointed_target()? {
                Some(pointed) => {
                    target = in_odom(robot, &pointed)?;
                    seen = look(robot, &target, sweep, &again)?;
                }
                None => report.note("nobody pointed again"),
            }
        }
    }
    Ok(seen)
}

/// Drives to the plan's waypoint, facing the tag; returns the tag's centre in the odometry
/// frame, or `None` (with the reason in the report) when there is no way to approach it: no
/// tag, no surface behind it, or a blocked waypoint. `sized`: the search was bounded by the
/// sizes registered for the home's tags.
pub(crate) fn drive_to_waypoint(
    robot: &impl MobileBase,
    plan: &ApproachPlan,
    sized: bool,
    report: &mut PhaseReport,
) -> Result<Option<Point3<f64>>, HalError> {
    let Some(sighting) = &plan.tag else {
        // The search's last word says why red it saw was not taken (a region larger than any
        // tag); without one, there was no red at all.
        match plan.tag_notes.last() {
            Some(why) => report.fail_advising(
                format!("no tag taken near the pointed location: {why}"),
                too_large_advice(sized),
            ),
            None => report.fail_advising(
                "no red tag near the pointed location",
                "it saw nothing red where you pointed; point at the red tag itself",
            ),
        }
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
        report.fail_advising(
            format!(
                "no surface behind the tag among {} planes ({})",
                plan.planes.len(),
                nearest_rejection(plan)
            ),
            "it found the tag but could not make out the surface it is on; point at it again \
             from where more of that surface shows",
        );
        return Ok(None);
    };
    report.note(format!(
        "backing plane: {} points, {} planes in the volume of interest",
        plane.points,
        plan.planes.len()
    ));
    if let Some(Clearance::Blocked { points, .. }) = plan.clearance {
        report.fail_advising(
            format!("the waypoint is blocked ({points} points inside the robot's outline)"),
            "something stands on the floor in front of the tag, where the robot must be; clear \
             it away",
        );
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

/// Why the plane nearest the tag was not taken, for the report.
fn nearest_rejection(plan: &ApproachPlan) -> String {
    let Some(tag) = plan.tag.as_ref().map(|s| s.nearest().centroid) else {
        return "no tag".into();
    };
    plan.rejected_planes
        .iter()
        .min_by(|a, b| off_plane(a, &tag).total_cmp(&off_plane(b, &tag)))
        .map_or("no plane was even tried".into(), |r| format!("the nearest: {}", r.why))
}

/// How far `point` (base frame) lies off a rejected plane, metres.
fn off_plane(plane: &RejectedPlane, point: &Point3<f64>) -> f64 {
    (plane.normal.dot(&point.coords) + plane.offset).abs()
}

/// Moves the base to look at the tag from a better place: square to the vertical surface the
/// look half saw nearest the tag (a front seen too obliquely, or too sparsely to pass as one),
/// at the same distance; or, with no such surface, 0.3 m further back for a wider view. Says
/// where it went; `false` when it did not move.
fn step_to_a_better_view(
    robot: &(impl ColorCamera + TiltingLaser + MobileBase),
    plan: &ApproachPlan,
    report: &mut PhaseReport,
) -> Result<bool, HalError> {
    let Some(tag) = plan.tag.as_ref().map(|s| s.nearest().centroid) else { return Ok(false) };
    let here = Vector2::new(tag.x, tag.y);
    let distance = here.norm().clamp(0.8, 1.3);
    // The surface is the vertical plane nearest the tag, its normal toward the robot.
    let facing = plan
        .rejected_planes
        .iter()
        .filter(|r| r.normal.z.abs() < 20f64.to_radians().sin())
        .filter(|r| off_plane(r, &tag) < 0.1)
        .min_by(|a, b| off_plane(a, &tag).total_cmp(&off_plane(b, &tag)))
        .and_then(|r| Vector2::new(r.normal.x, r.normal.y).try_normalize(1e-6));
    match facing {
        Some(out) if out.dot(&-here.normalize()).acos() > 15f64.to_radians() => {
            let stand = here + out * distance;
            robot.move_relative(stand, (-out.y).atan2(-out.x))?;
            report.note(format!(
                "stepped {:.2} m to look square at the surface the tag seems to be on, \
                 {:.2} m out from it",
                stand.norm(),
                distance
            ));
            Ok(true)
        }
        _ => {
            robot.drive(-0.3)?;
            report.note("backed off 0.3 m for a wider view of the tag's surroundings");
            Ok(true)
        }
    }
}
