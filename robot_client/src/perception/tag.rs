//! Finding the PPS-tag near a target point: the paper's §III-B, step by step.

use std::collections::{BTreeMap, BTreeSet, HashSet};

use nalgebra::Point3;

use super::blobs::Blobs;
use super::bounded_tag::{bound_tags, too_large_nearest};
use super::occupancy::{Component, OccupancyGrid};
use super::projection::{ProjectedCloud, Reach};
use super::seeded_segmentation::segment_seeded;
use super::tag_bound::TagBound;
use super::tag_search_params::TagSearchParams;
use super::tag_sighting::{TagDetection, TagSighting};
use crate::hal::{CameraCalibration, ColorImage, PointCloud};
use crate::timings::StepTimings;

/// Why the search could not run at all (as opposed to finding nothing).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PerceptionError {
    #[error("the image is {image:?} pixels but the camera calibration is for {camera:?}")]
    ImageSizeMismatch { image: (u32, u32), camera: (u32, u32) },
}

/// What the tag search saw near the target, and what it has to say about it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TagSearch {
    pub sighting: Option<TagSighting>,
    /// Red regions divided because no tag is that large, or why none was taken, in words.
    pub notes: Vec<String>,
}

/// Finds the tag nearest `target` (base frame) in a registered image and cloud, timing each step
/// into `timings`. `Ok(None)` when nothing red enough lies near the target.
pub fn locate_tag(
    image: &ColorImage,
    cloud: &PointCloud,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    timings: &mut StepTimings,
) -> Result<Option<TagSighting>, PerceptionError> {
    Ok(search_tag(image, cloud, calibration, target, params, timings)?.sighting)
}

/// [`locate_tag`], with the notes on the red regions that were divided or refused.
pub fn search_tag(
    image: &ColorImage,
    cloud: &PointCloud,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    timings: &mut StepTimings,
) -> Result<TagSearch, PerceptionError> {
    let k = &calibration.intrinsics;
    if (image.width, image.height) != (k.width, k.height) {
        return Err(PerceptionError::ImageSizeMismatch {
            image: (image.width, image.height),
            camera: (k.width, k.height),
        });
    }
    // The cloud in the image first: the segmentation starts from where its points land. Only
    // a red region holding a point this near the target can hold the tag or a fragment of it
    // (see `join_fragments`), so only those regions are segmented.
    let reach = Reach { centre: *target, radius: params.max_distance + params.fragment_gap };
    let view = timings.time("project", || {
        ProjectedCloud::new(&cloud.points, calibration, &params.occlusion, &reach)
    });
    // 1. 2D segmentation of red by minimum and maximum HSV thresholds, of the regions the laser
    //    saw near the target.
    let raw = timings.time("segment", || segment_seeded(image, &params.thresholds, view.seen()));
    // 2. Morphology on the raw segmentation: hole filling, closing, then opening.
    let red = timings.time("morphology", || {
        raw.fill_holes().close(params.close_radius_px).open(params.open_radius_px)
    });
    // 3. Keep the points that land on red, unless nearer points hide them from the camera.
    let red_points =
        timings.time("project", || view.on_mask(&cloud.points, &red, &params.occlusion));
    // 4. A 1 cm³ occupancy grid of the red points.
    let grid =
        timings.time("occupancy_grid", || OccupancyGrid::new(&red_points, params.voxel_size));
    // 5. 3D connected components, the fragments of one red region joined, each larger than
    //    any tag divided; keep the one closest to the target.
    Ok(timings.time("components", || {
        let components = grid.connected_components(target);
        let blobs = Blobs::of(&red);
        let joined = join_fragments(components, &blobs, calibration, params);
        let mut notes = Vec::new();
        let join = |parts| join_fragments(parts, &blobs, calibration, params);
        let bound = TagBound::new(params, calibration);
        let bounded =
            bound_tags(joined, image, calibration, target, params, &bound, &join, &mut notes);
        let sighting = choose_tag(bounded.clone(), params, &bound);
        notes.extend(too_large_nearest(
            &bounded,
            sighting.as_ref().map(TagSighting::nearest),
            params,
            &bound,
        ));
        TagSearch { sighting, notes }
    }))
}

/// Joins components whose points fall in one blob of the image and come within
/// `params.fragment_gap` of each other: one tag that the laser sampled too sparsely (a towel at
/// a steep angle, a line of dropouts) for its voxels to touch. Components far from the target are
/// left as they are. Blobs and components are visited in order, so the result is the same on
/// every run.
fn join_fragments(
    components: Vec<Component>,
    blobs: &Blobs,
    calibration: &CameraCalibration,
    params: &TagSearchParams,
) -> Vec<Component> {
    let (near, far): (Vec<Component>, Vec<Component>) = components
        .into_iter()
        .partition(|c| c.distance_to_target <= params.max_distance + params.fragment_gap);
    if near.len() < 2 {
        return near.into_iter().chain(far).collect();
    }
    let camera_from_base = calibration.base_from_camera.inverse();
    let k = &calibration.intrinsics;
    let gap = params.fragment_gap;
    let cell = |p: &Point3<f32>| [p.x, p.y, p.z].map(|v| (f64::from(v) / gap).floor() as i64);
    // Each component's blobs and coarse cells.
    let mut by_blob: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    let mut cells: Vec<HashSet<[i64; 3]>> = Vec::with_capacity(near.len());
    for (i, c) in near.iter().enumerate() {
        let mut own = BTreeSet::new();
        for p in &c.members {
            let pixel = k.project(&(camera_from_base * p.cast::<f64>()));
            if let Some(blob) = pixel.and_then(|uv| {
                (uv.x >= 0.0 && uv.y >= 0.0).then(|| blobs.at(uv.x as usize, uv.y as usize))?
            }) {
                own.insert(blob);
            }
        }
        for blob in own {
            by_blob.entry(blob).or_default().push(i);
        }
        cells.push(c.members.iter().map(cell).collect());
    }
    let touches = |a: &HashSet<[i64; 3]>, b: &HashSet<[i64; 3]>| {
        let (small, large) = if a.len() <= b.len() { (a, b) } else { (b, a) };
        small.iter().any(|[x, y, z]| {
            (-1..=1).any(|dx| {
                (-1..=1).any(|dy| (-1..=1).any(|dz| large.contains(&[x + dx, y + dy, z + dz])))
            })
        })
    };
    let mut parent: Vec<usize> = (0..near.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for members in by_blob.values() {
        for (n, &a) in members.iter().enumerate() {
            for &b in &members[n + 1..] {
                if root(&mut parent, a) != root(&mut parent, b) && touches(&cells[a], &cells[b]) {
                    let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                    parent[ra] = rb;
                }
            }
        }
    }
    let mut joined: BTreeMap<usize, Component> = BTreeMap::new();
    for (i, c) in near.into_iter().enumerate() {
        let r = root(&mut parent, i);
        match joined.remove(&r) {
            Some(whole) => joined.insert(r, whole.joined_with(c)),
            None => joined.insert(r, c),
        };
    }
    joined.into_values().chain(far).collect()
}

/// Whether `part` is about as near the target as `than`, or nearer: within the pointing's
/// ambiguity, as a tag beside a red thing the person pointed at may be.
pub(super) fn about_as_near(part: &Component, than: &Component, params: &TagSearchParams) -> bool {
    part.distance_to_target <= than.distance_to_target + params.ambiguity_margin
}

/// The component closest to the target among those big enough to be a tag and near enough to
/// be the one meant, when it is no larger than any tag (`bound`); ambiguous when another tag,
/// apart from it, is nearly as close. None when the closest is larger than any tag: the red
/// thing the person pointed at is not a tag, and a red thing farther away is not what they
/// meant.
pub(super) fn choose_tag(
    components: Vec<Component>,
    params: &TagSearchParams,
    bound: &TagBound,
) -> Option<TagSighting> {
    let mut near: Vec<Component> = components
        .into_iter()
        .filter(|c| c.points >= params.min_points && c.distance_to_target <= params.max_distance)
        .collect();
    near.sort_by(|a, b| a.distance_to_target.total_cmp(&b.distance_to_target));
    let (first, rest) = near.split_first()?;
    // A red thing larger than any tag nearest the pointed location is not what the person
    // meant, and a tag about as near as it (within the pointing's ambiguity) beside it may be;
    // one farther away is not.
    let first_is_a_tag = bound.holds(first);
    let candidates: Vec<&Component> = first_is_a_tag
        .then_some(first)
        .into_iter()
        .chain(
            rest.iter()
                .filter(|c| (first_is_a_tag || about_as_near(c, first, params)) && bound.holds(c)),
        )
        .collect();
    let nearest = TagDetection::from(*candidates.first()?);
    let rival = candidates[1..].iter().find(|c| {
        (c.centroid - nearest.centroid).norm() >= params.min_tag_separation
            && c.distance_to_target - nearest.distance_to_target < params.ambiguity_margin
    });
    Some(match rival {
        Some(other) => TagSighting::Ambiguous { nearest, other: (*other).into() },
        _ => TagSighting::Found(nearest),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::head_camera;

    /// `params`' bound on a tag, seen by the simulator's head camera.
    fn bound(params: &TagSearchParams) -> TagBound {
        TagBound::new(params, &head_camera(1.0))
    }

    fn component(distance: f64, points: usize) -> Component {
        Component {
            centroid: Point3::new(distance, 0.0, 0.0),
            points,
            voxels: points / 2,
            distance_to_target: distance,
            radius: 0.05,
            members: Vec::new(),
        }
    }

    #[test]
    fn specks_and_far_lumps_are_not_tags() {
        let params = TagSearchParams::default();
        assert_eq!(
            choose_tag(vec![component(0.01, 3), component(0.9, 400)], &params, &bound(&params)),
            None
        );
        let found = choose_tag(
            vec![component(0.01, 3), component(0.05, 40), component(0.3, 400)],
            &params,
            &bound(&params),
        );
        assert_eq!(found, Some(TagSighting::Found(TagDetection::from(&component(0.05, 40)))));
    }

    #[test]
    fn a_red_thing_farther_than_one_larger_than_any_tag_is_not_taken() {
        let params = TagSearchParams::default();
        let mut too_large = component(0.02, 5000);
        too_large.radius = params.max_tag_radius * 1.5;
        let mug = component(0.25, 300);
        assert_eq!(
            choose_tag(vec![too_large.clone(), mug.clone()], &params, &bound(&params)),
            None
        );
        // Farther than the mug, the large thing does not stand in its way.
        too_large.distance_to_target = 0.3;
        let found = choose_tag(vec![too_large, mug.clone()], &params, &bound(&params));
        assert_eq!(found, Some(TagSighting::Found(TagDetection::from(&mug))));
    }

    #[test]
    fn a_tag_about_as_near_as_a_red_thing_larger_than_any_tag_is_taken_beside_it() {
        let params = TagSearchParams::default();
        // A red box standing prouder than a foam tube beside it, nearer the pointed location.
        let mut red_box = component(0.02, 5000);
        red_box.radius = params.max_tag_radius * 1.5;
        let tube = component(0.035, 300);
        let found = choose_tag(vec![red_box.clone(), tube.clone()], &params, &bound(&params));
        assert_eq!(found, Some(TagSighting::Found(TagDetection::from(&tube))));
        // Beyond the pointing's ambiguity, it is not what the person meant.
        let far = component(0.02 + params.ambiguity_margin + 0.01, 300);
        assert_eq!(choose_tag(vec![red_box.clone(), far.clone()], &params, &bound(&params)), None);
        // And the notes say which, and why.
        let taken = TagDetection::from(&tube);
        let said =
            too_large_nearest(&[red_box.clone(), tube], Some(&taken), &params, &bound(&params))
                .unwrap();
        let beside = "the tag-sized part beside it (300 points, 4 cm from the target) is taken";
        assert!(said.ends_with(&format!("{beside} for the tag")), "{said}");
        let said = too_large_nearest(&[red_box, far], None, &params, &bound(&params)).unwrap();
        assert!(said.ends_with("so it is not taken for a tag"), "{said}");
    }

    #[test]
    fn two_tags_about_as_near_are_ambiguous_but_a_fringe_is_not_a_tag() {
        let params = TagSearchParams::default();
        let mut apart = component(0.15, 80);
        apart.centroid = Point3::new(0.0, 0.3, 0.0);
        let sighting =
            choose_tag(vec![component(0.12, 50), apart], &params, &bound(&params)).unwrap();
        assert!(sighting.is_ambiguous());
        assert_eq!(sighting.nearest().points, 50);
        // A strip of the surface behind a tag's edge, 5 cm from its centroid.
        let mut fringe = component(0.13, 15);
        fringe.centroid = Point3::new(0.12, 0.05, 0.0);
        let sighting =
            choose_tag(vec![component(0.12, 500), fringe], &params, &bound(&params)).unwrap();
        assert!(!sighting.is_ambiguous());
    }
}
