//! The approach, end to end on one image and one cloud (paper §IV-B.1.a): the volume of interest,
//! all planes in it, the tag (§III-B), the backing plane, the waypoint and its collision check.
//!
//! The paper chose the plane before finding the tag; here the tag is found first because the
//! backing-plane rule needs its centroid, and because the tag's own points are no evidence of
//! the surface behind it: a towel standing proud of a narrow front would otherwise thicken the
//! front into something that looks like a slab, or be taken for the front itself.

use nalgebra::{Point3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::backing_plane::{BackingPlane, BackingPlaneRule, choose_backing_plane};
use super::ransac::{DetectedPlane, PlaneSearch, PlaneSearchParams, find_planes};
use super::rejection::RejectedPlane;
use super::tag_centre::{FACE_DEPTH, tag_centre_on};
use super::voi::VolumeOfInterest;
use super::waypoint::{
    ApproachWaypoint, Clearance, RobotFootprint, approach_waypoint, check_clearance,
};
use crate::hal::{CameraCalibration, ColorImage, PointCloud};
use crate::perception::{
    DepthNoise, OccupancyGrid, OrganisedCloud, PerceptionError, RaySmoothing, TagSearchParams,
    TagSighting, search_tag,
};
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
    /// How the range sensor's depth scatters with range: every range-dependent tolerance above
    /// is widened to the noise at the target's range (see [`ApproachParams::at_range`]).
    pub depth_noise: DepthNoise,
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
            depth_noise: DepthNoise::LASER,
        }
    }
}

impl ApproachParams {
    /// These parameters for a target `range` metres from the sensor, with the tolerances that
    /// depend on the depth noise sized by the noise there, once smoothed along the rays.
    pub fn at_range(&self, range: f64) -> Self {
        let sigma = self.depth_noise.smoothed_sigma_at(range);
        Self {
            tag: self.tag.for_depth_noise(sigma),
            planes: self.planes.for_depth_noise(sigma),
            backing: self.backing.for_depth_noise(sigma),
            ..self.clone()
        }
    }
}

/// What the approach found; each later part is `None` when an earlier one found nothing.
#[derive(Debug, Clone, PartialEq)]
pub struct ApproachPlan {
    pub tag: Option<TagSighting>,
    /// What the tag search has to say: red regions divided because no tag is that large, or
    /// why none near the target was taken.
    pub tag_notes: Vec<String>,
    /// The points in the volume of interest, the tag's own left out: what the planes were
    /// searched in, and what their inlier indices refer to.
    pub surface_points: Vec<Point3<f32>>,
    /// Points in the volume of interest, the tag's included.
    pub voi_points: usize,
    /// The surfaces found among them, largest first.
    pub planes: Vec<DetectedPlane>,
    /// Index into `planes` of the backing plane.
    pub backing_index: Option<usize>,
    pub backing_plane: Option<BackingPlane>,
    /// Every plane not taken and why: first the search's non-surfaces, then the surfaces the
    /// backing-plane rule turned down.
    pub rejected_planes: Vec<RejectedPlane>,
    pub waypoint: Option<ApproachWaypoint>,
    pub clearance: Option<Clearance>,
    pub timings: StepTimings,
}

impl ApproachPlan {
    /// Whether the search saw nothing of the tag's colour near the target: no tag, and no red
    /// region it divided or turned down.
    pub fn saw_nothing_red(&self) -> bool {
        self.tag.is_none() && self.tag_notes.is_empty()
    }

    /// The laser's noise across surfaces here (standard deviation, metres): the median over
    /// the planes found, `None` when none was.
    pub fn laser_noise(&self) -> Option<f64> {
        let mut noise: Vec<f64> = self.planes.iter().map(|p| p.noise).collect();
        noise.sort_by(f64::total_cmp);
        noise.get(noise.len() / 2).copied()
    }
}

/// Runs the approach on one registered image and cloud (base frame) around `target`.
pub fn plan_approach(
    image: &ColorImage,
    cloud: &PointCloud,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &ApproachParams,
) -> Result<ApproachPlan, PerceptionError> {
    let clearance =
        |w: &ApproachWaypoint| check_clearance(&cloud.points, w, w.position.z, &params.footprint);
    let points = Points::Cloud(cloud);
    plan_approach_with(
        image,
        points,
        calibration,
        target,
        params,
        StepTimings::default(),
        clearance,
    )
}

/// The points the approach runs on: any cloud, or a depth image's own, whose points know their
/// pixels.
pub(crate) enum Points<'a> {
    Cloud(&'a PointCloud),
    Organised(OrganisedCloud<'a>),
}

/// The approach on `points`, which must hold every point of the volume of interest and of the
/// tag's reach; `clearance` checks the waypoint against whatever the caller holds around it.
/// Steps already timed come in `timings`.
pub(crate) fn plan_approach_with(
    image: &ColorImage,
    points: Points<'_>,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &ApproachParams,
    mut timings: StepTimings,
    clearance: impl FnOnce(&ApproachWaypoint) -> Clearance,
) -> Result<ApproachPlan, PerceptionError> {
    // The robot's sensors sit near the camera: planes face there, and so must the backing plane.
    let robot = Point3::from(calibration.base_from_camera.translation.vector);
    let range = (target - robot).norm();
    // A depth camera's fog at this range, smoothed along its rays around the target; the
    // tolerances below are sized by what noise is left.
    let window = params.depth_noise.smoothing_window(range);
    let reach = params.voi_radius.max(params.tag.max_distance + params.tag.fragment_gap);
    let half = Vector3::new(reach, reach, params.voi_half_height.max(reach));
    let smoothing = RaySmoothing {
        image,
        tag: &params.tag.thresholds,
        calibration,
        min: target - half,
        max: target + half,
        window,
        noise: &params.depth_noise,
    };
    let smoothed;
    let organised;
    let cloud = match points {
        Points::Cloud(cloud) if window > 1 => {
            smoothed = timings.time("ray_smoothing", || PointCloud {
                points: smoothing.of_points(&cloud.points),
            });
            &smoothed
        }
        Points::Cloud(cloud) => cloud,
        Points::Organised(mut cloud) => {
            if window > 1 {
                timings.time("ray_smoothing", || smoothing.of_organised(&mut cloud));
            }
            organised = cloud;
            organised.cloud()
        }
    };
    let raw_sigma = params.depth_noise.sigma_at(range);
    let params = &params.at_range(range);
    let voi = VolumeOfInterest::around(*target, params.voi_radius, params.voi_half_height);
    // The crop needs nothing of the tag, so a second core makes it while the tag is searched
    // for; its time is inside the tag steps' wall time, not under "volume_of_interest".
    let (tag, inside) = rayon::join(
        || search_tag(image, cloud, calibration, target, &params.tag, &mut timings),
        || voi.crop(&cloud.points),
    );
    let search = tag?;
    let (mut tag, tag_notes) = (search.sighting, search.notes);
    let (voi_points, surface_points) = timings.time("volume_of_interest", || {
        let count = inside.len();
        let surface = match &tag {
            Some(sighting) => {
                let own = OccupancyGrid::new(&sighting.nearest().members, params.tag.voxel_size);
                inside.into_iter().filter(|p| !own.contains(p)).collect()
            }
            None => inside,
        };
        (count, surface)
    });
    let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
    let PlaneSearch { planes, rejected: mut rejected_planes } =
        timings.time("ransac", || find_planes(&surface_points, &robot, &params.planes, &mut rng));
    let choice = timings.time("backing_plane", || {
        let tag = tag.as_ref()?.nearest();
        Some(choose_backing_plane(
            &planes,
            &surface_points,
            &tag.centroid,
            tag.radius,
            &tag.members,
            &robot,
            &params.backing,
        ))
    });
    let (backing_index, backing_plane) = match choice {
        Some(choice) => {
            rejected_planes.extend(choice.rejected);
            (choice.index, choice.plane)
        }
        None => (None, None),
    };
    // With the surface known, the tag's centre is the middle of its outline on it; placed by
    // the points' directions alone where their depths are rougher than a tag's face is deep.
    let rough = raw_sigma > FACE_DEPTH / 3.0;
    let rays_from = rough.then_some(&robot);
    if let (Some(sighting), Some(plane)) = (tag.as_mut(), &backing_plane) {
        let nearest = sighting.nearest_mut();
        if let Some(centre) = tag_centre_on(&nearest.members, plane, rays_from) {
            nearest.centroid = centre;
        }
    }
    let waypoint = timings.time("waypoint", || {
        approach_waypoint(
            &tag.as_ref()?.nearest().centroid,
            backing_plane.as_ref()?,
            params.standoff,
        )
    });
    let clearance = timings.time("collision_check", || Some(clearance(waypoint.as_ref()?)));
    Ok(ApproachPlan {
        tag,
        tag_notes,
        surface_points,
        voi_points,
        planes,
        backing_index,
        backing_plane,
        rejected_planes,
        waypoint,
        clearance,
        timings,
    })
}
