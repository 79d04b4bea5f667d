//! The approach on an RGB-D camera's organised frame: a dense depth image aligned to the colour
//! image holds 0.3–1 M points, 2–5× a laser sweep, most of them far from the target. Every
//! pixel's ray is known before its depth is read, so only the pixels whose rays can meet the
//! volume of interest or the tag's reach become points, and for the collision check only those
//! that can meet the robot's boxes at the waypoint. The answer is the one the whole frame's
//! cloud gives: the same points of those boxes, in the same order.

use nalgebra::{Point3, Vector3};

use super::approach::{ApproachParams, ApproachPlan, Points, plan_approach_with};
use super::waypoint::{ApproachWaypoint, Clearance, check_clearance};
use crate::hal::{CameraCalibration, ColorImage};
use crate::perception::{
    DepthImage, DepthRange, DepthSizeMismatch, PerceptionError, PixelWindow, cloud_from_depth_in,
    organised_cloud_from_depth_in,
};
use crate::timings::StepTimings;

/// Why the approach could not run on a depth frame.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DepthApproachError {
    #[error(transparent)]
    Depth(#[from] DepthSizeMismatch),
    #[error(transparent)]
    Perception(#[from] PerceptionError),
}

/// Runs the approach on one colour image and its aligned depth around `target`, converting
/// only the pixels that can matter; `depth_to_cloud` times the conversion of the volume's.
pub fn plan_approach_on_depth(
    image: &ColorImage,
    depth: &DepthImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    range: &DepthRange,
    params: &ApproachParams,
) -> Result<ApproachPlan, DepthApproachError> {
    let mut timings = StepTimings::default();
    // The tag search reaches a little beyond the volume (the fragments' gap), and its occlusion
    // test compares a point with the others of its depth cell, up to a cell's width away.
    let reach = params.tag.max_distance + params.tag.fragment_gap;
    let half = Vector3::new(
        params.voi_radius.max(reach),
        params.voi_radius.max(reach),
        params.voi_half_height.max(reach),
    );
    let k = &calibration.intrinsics;
    let cell_px = (params.tag.occlusion.cell_angle * k.fx.max(k.fy)).ceil() as u32 + 2;
    let window = PixelWindow::of_box(calibration, &(target - half), &(target + half), cell_px);
    let cloud = timings.time("depth_to_cloud", || {
        organised_cloud_from_depth_in(depth, calibration, range, &window)
    })?;
    let mut refused = None;
    let clearance = |w: &ApproachWaypoint| {
        let reach = params.footprint.reach();
        let f = &params.footprint;
        let min = Point3::new(w.position.x - reach, w.position.y - reach, f.floor_clearance);
        let max = Point3::new(w.position.x + reach, w.position.y + reach, f.height);
        let around = PixelWindow::of_box(calibration, &min, &max, 1);
        match cloud_from_depth_in(depth, calibration, range, &around) {
            Ok(near) => check_clearance(&near.points, w, w.position.z, f),
            Err(e) => {
                refused = Some(e);
                Clearance::Clear
            }
        }
    };
    let points = Points::Organised(cloud);
    let plan = plan_approach_with(image, points, calibration, target, params, timings, clearance)?;
    match refused {
        Some(e) => Err(e.into()),
        None => Ok(plan),
    }
}
