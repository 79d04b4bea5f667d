//! The approach, end to end on one image and one cloud (paper §IV-B.1.a): the volume of interest,
//! all planes in it, the tag (§III-B), the backing plane, the waypoint and its collision check.
//!
//! The paper chose the plane before finding the tag; here the tag is found first because the
//! backing-plane rule needs its centroid.

use nalgebra::Point3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::backing_plane::{BackingPlane, BackingPlaneRule, choose_backing_plane};
use super::ransac::{PlaneSearchParams, find_planes};
use super::voi::VolumeOfInterest;
use super::waypoint::{
    ApproachWaypoint, Clearance, RobotFootprint, approach_waypoint, check_clearance,
};
use crate::hal::{CameraCalibration, ColorImage, PointCloud};
use crate::perception::{PerceptionError, TagSearchParams, TagSighting, locate_tag};
use crate::timings::StepTimings;

/// Everything the approach is tuned by.
#[derive(Debug, Clone, PartialEq)]
pub struct ApproachParams {
    pub tag: TagSearchParams,
    /// Radius and half height of the volume of interest, metres.
    pub voi_radius: f64,
    pub voi_half_height: f64,
    pub planes: PlaneSearchParams,
    pub backing: BackingPlaneRule,
    /// Distance of the waypoint from the tag, metres (the paper's 50 cm).
    pub standoff: f64,
    pub footprint: RobotFootprint,
    /// Seed of the plane search's sampling, so the same data gives the same answer.
    pub seed: u64,
}

impl Default for ApproachParams {
    fn default() -> Self {
        Self {
            tag: TagSearchParams::default(),
            voi_radius: 0.5,
            voi_half_height: 0.5,
            planes: PlaneSearchParams::default(),
            backing: BackingPlaneRule::default(),
            standoff: 0.5,
            footprint: RobotFootprint::default(),
            seed: 0,
        }
    }
}

/// What the approach found; each later part is `None` when an earlier one found nothing.
#[derive(Debug, Clone, PartialEq)]
pub struct ApproachPlan {
    pub tag: Option<TagSighting>,
    /// Points in the volume of interest and planes found among them.
    pub voi_points: usize,
    pub planes: usize,
    pub backing_plane: Option<BackingPlane>,
    pub waypoint: Option<ApproachWaypoint>,
    pub clearance: Option<Clearance>,
    pub timings: StepTimings,
}

/// Runs the approach on one registered image and cloud (base frame) around `target`.
pub fn plan_approach(
    image: &ColorImage,
    cloud: &PointCloud,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &ApproachParams,
) -> Result<ApproachPlan, PerceptionError> {
    let mut timings = StepTimings::default();
    let tag = locate_tag(image, cloud, calibration, target, &params.tag, &mut timings)?;
    // The robot's sensors sit near the camera: planes face there, and so must the backing plane.
    let robot = Point3::from(calibration.base_from_camera.translation.vector);
    let voi = VolumeOfInterest::around(*target, params.voi_radius, params.voi_half_height);
    let voi_points = timings.time("volume_of_interest", || voi.crop(&cloud.points));
    let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
    let planes =
        timings.time("ransac", || find_planes(&voi_points, &robot, &params.planes, &mut rng));
    let backing_plane = timings.time("backing_plane", || {
        let tag = tag.as_ref()?.nearest();
        choose_backing_plane(&planes, &voi_points, &tag.centroid, &robot, &params.backing)
    });
    let waypoint = timings.time("waypoint", || {
        approach_waypoint(
            &tag.as_ref()?.nearest().centroid,
            backing_plane.as_ref()?,
            params.standoff,
        )
    });
    let clearance = timings.time("collision_check", || {
        let w = waypoint.as_ref()?;
        Some(check_clearance(&cloud.points, w, w.position.z, &params.footprint))
    });
    Ok(ApproachPlan {
        tag,
        voi_points: voi_points.len(),
        planes: planes.len(),
        backing_plane,
        waypoint,
        clearance,
        timings,
    })
}
