//! Phase 1 (paper §IV-B): "when EL-E is further than a threshold distance away (1.0 m), the
//! robot will drive towards the given location." It turns to face the location and drives
//! until its front is within the threshold, never so far that the location would leave the
//! camera's view (phase 2 needs to see the tag).
//!
//! Points the task carries between phases live in the odometry frame, so that they stay put
//! while the base moves.

use nalgebra::{Isometry3, Point3, Vector3};

use super::report::PhaseReport;
use crate::behaviors::RobotBody;
use crate::hal::{CameraCalibration, HalError, MobileBase, PlanarPose};

/// The odometry frame's pose of the base, as a 3D isometry.
pub(crate) fn odom_from_base(pose: &PlanarPose) -> Isometry3<f64> {
    Isometry3::new(
        Vector3::new(pose.translation.x, pose.translation.y, 0.0),
        Vector3::z() * pose.rotation.angle(),
    )
}

/// A point of the odometry frame, in the base frame now.
pub(crate) fn in_base(base: &impl MobileBase, odom: &Point3<f64>) -> Result<Point3<f64>, HalError> {
    Ok(odom_from_base(&base.pose_estimate()?).inverse() * odom)
}

/// A point of the base frame now, in the odometry frame.
pub(crate) fn in_odom(base: &impl MobileBase, p: &Point3<f64>) -> Result<Point3<f64>, HalError> {
    Ok(odom_from_base(&base.pose_estimate()?) * p)
}

/// Where the camera's lens is, base frame.
pub(crate) fn camera_origin(calibration: &CameraCalibration) -> Point3<f64> {
    Point3::from(calibration.base_from_camera.translation.vector)
}

/// Whether `p` (base frame) falls inside the camera's image with a margin (fraction of its size).
pub(crate) fn in_view(calibration: &CameraCalibration, p: &Point3<f64>, margin: f64) -> bool {
    let k = &calibration.intrinsics;
    let optical = calibration.base_from_camera.inverse() * p;
    k.project(&optical).is_some_and(|px| {
        let (w, h) = (f64::from(k.width), f64::from(k.height));
        px.x >= margin * w
            && px.x <= (1.0 - margin) * w
            && px.y >= margin * h
            && px.y <= (1.0 - margin) * h
    })
}

/// Drives toward `target` (odometry frame) until the base's front is within `near_enough`.
pub(crate) fn drive_toward(
    base: &impl MobileBase,
    calibration: &CameraCalibration,
    body: &RobotBody,
    target: &Point3<f64>,
    near_enough: f64,
    report: &mut PhaseReport,
) -> Result<(), HalError> {
    let here = in_base(base, target)?;
    let heading = here.y.atan2(here.x);
    base.turn(heading)?;
    let here = in_base(base, target)?;
    let ahead = here.x.hypot(here.y) - body.palm_ahead;
    let mut distance = (ahead - near_enough).max(0.0);
    // Keep the pointed location in the camera's view, or phase 2 cannot see the tag.
    while distance > 0.0 && !in_view(calibration, &(here - Vector3::x() * distance), 0.1) {
        distance = (distance - 0.05).max(0.0);
    }
    base.drive(distance)?;
    report.note(format!(
        "the pointed location was {ahead:.2} m ahead of the base's front; turned {:.0}° and drove {distance:.2} m",
        heading.to_degrees()
    ));
    Ok(())
}
