//! A container's opening, found around the PPS-tag on its front (paper §IV-B.2.f): "segment out
//! all planes in a cylindrical volume around the PPS-tag, select the closest plane to the
//! PPS-tag, calculate the orientation of the plane, and find a point above the container from
//! which to drop the object."

use nalgebra::Point3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{
    BackingPlane, BackingPlaneRule, DetectedPlane, PlaneSearchParams, VolumeOfInterest,
    choose_backing_plane, find_planes,
};

/// The cylinder searched around the tag: a bin's front and its rim, not the room around it.
const SEARCH_RADIUS: f64 = 0.4;
const SEARCH_HALF_HEIGHT: f64 = 0.5;
/// The tag on a container is a flat patch: 5 cm of reach is plenty for the foot-gap rule.
const TAG_RADIUS: f64 = 0.05;
/// A surface within this tilt of level may be the container's top.
const LEVEL_TILT_DEG: f64 = 20.0;
/// With no top seen, the drop point is a hand's width behind the front, at the tag's height.
const HAND_WIDTH: f64 = 0.1;

/// Where to drop, and what was seen on the way to it.
#[derive(Debug, Clone, PartialEq)]
pub struct ContainerOpening {
    /// The container's front, the plane carrying the tag.
    pub front: BackingPlane,
    /// A point over the opening, base frame, metres.
    pub drop_point: Point3<f64>,
}

/// What the scan around the tag showed.
#[derive(Debug, Clone, PartialEq)]
pub struct ContainerSearch {
    /// Points inside the searched cylinder.
    pub points: usize,
    /// Planes found among them.
    pub planes: usize,
    /// `None` when no plane could be the container's front.
    pub opening: Option<ContainerOpening>,
}

/// Finds the opening of the container whose front carries the tag at `tag`, in a cloud taken
/// by a laser at `sensor`; `seed` makes the plane search repeatable.
pub fn find_container_opening(
    cloud: &[Point3<f32>],
    tag: &Point3<f64>,
    sensor: &Point3<f64>,
    seed: u64,
) -> ContainerSearch {
    let points = VolumeOfInterest::around(*tag, SEARCH_RADIUS, SEARCH_HALF_HEIGHT).crop(cloud);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let planes = find_planes(&points, sensor, &PlaneSearchParams::default(), &mut rng).planes;
    let front = choose_backing_plane(
        &planes,
        &points,
        tag,
        TAG_RADIUS,
        &[],
        sensor,
        &BackingPlaneRule::default(),
    )
    .plane;
    let opening = front.map(|front| ContainerOpening {
        drop_point: top_behind(&planes, &front, tag)
            .map_or_else(|| tag - front.normal * HAND_WIDTH, |top| top.centroid),
        front,
    });
    ContainerSearch { points: points.len(), planes: planes.len(), opening }
}

/// The level surface behind the front and above the tag, nearest the tag: the container's top,
/// not the floor below it or a table beyond it.
fn top_behind<'a>(
    planes: &'a [DetectedPlane],
    front: &BackingPlane,
    tag: &Point3<f64>,
) -> Option<&'a DetectedPlane> {
    let level = LEVEL_TILT_DEG.to_radians().cos();
    planes
        .iter()
        .filter(|p| p.plane.normal.z.abs() > level)
        .filter(|p| p.centroid.z > tag.z)
        .filter(|p| front.normal.dot(&p.centroid.coords) + front.offset < 0.0)
        .min_by(|a, b| (a.centroid - tag).norm().total_cmp(&(b.centroid - tag).norm()))
}
