//! The size of a detected tag, for the trial (issue 34): once the fingers have read the tag's
//! EPC, the points the tag search took for it are known to be that tag, and the registry learns
//! the size of a tag nobody measured from them, so that the search is bounded by the home's
//! largest tag without a caretaker's tape measure.
//!
//! The size is the tag's extent on its backing surface: its points that have the colour of its
//! middle (those `tag_color` takes) projected onto the surface's level axis (the width) and the
//! axis along the surface at right angles to it (the height, up and down on a wall). Stray
//! points at the edges (a mixed return, a speck of red beside the tag) are trimmed off by taking
//! the 2nd to 98th percentile, which is then scaled back to the whole: of points spread evenly
//! over the tag, those percentiles span 96 % of it.
//!
//! Only for a look whose tag the fingers then read alone: a look at two tags, or at a red thing
//! that is no tag, would teach the registry a size no tag has. A red thing of the tag's own
//! colour touching it is still measured with it; the registry's median over visits is what
//! keeps one such look from counting.

use nalgebra::{Point3, Vector3};
use pps_schema::TagSize;

use super::bounded_tag::of_the_colour_at;
use super::tag_search_params::TagSearchParams;
use super::tag_sighting::TagDetection;
use crate::hal::{CameraCalibration, ColorImage};

/// Share of points trimmed off each end of the tag's extent, for stray points.
const TRIM: f64 = 0.02;

/// Fewest points a size is measured from: a 3 cm foam tube seen from 1.5 m gets 20 to 30
/// laser points; fewer are a tag seen in part, or not a tag.
const MIN_POINTS: usize = 20;

/// The smallest and largest width or height a trial may carry, metres (the schema's bounds).
const BOUNDS: std::ops::RangeInclusive<f64> = 0.01..=1.0;

/// The size of `tag` on the surface whose unit normal is `surface_normal` (base frame, z up),
/// from its points that have the colour of its middle, as `tag_color` takes them: wood or a
/// red neighbour the search joined to the tag (a region the size of a tag is not divided) is
/// left out. `None` for too few points or a size no tag has.
pub fn tag_size(
    image: &ColorImage,
    calibration: &CameraCalibration,
    tag: &TagDetection,
    params: &TagSearchParams,
    surface_normal: &Vector3<f64>,
) -> Option<TagSize> {
    let members = of_the_colour_at(&tag.members, image, calibration, &tag.centroid, params);
    extent_on(&members, surface_normal)
}

/// The extent of `members` (a tag's points, base frame, metres) on the surface whose unit normal
/// is `surface_normal`, millimetre-rounded; `None` for too few points or a size no tag has.
fn extent_on(members: &[Point3<f32>], surface_normal: &Vector3<f64>) -> Option<TagSize> {
    if members.len() < MIN_POINTS {
        return None;
    }
    let n = surface_normal.try_normalize(1e-9)?;
    // Level along the surface; on a floor or a table top (no level direction of its own),
    // the base's x.
    let across = n.cross(&Vector3::z()).try_normalize(1e-6).unwrap_or(Vector3::x());
    let along = n.cross(&across);
    let extent = |axis: &Vector3<f64>| {
        let values: Vec<f64> = members.iter().map(|p| axis.dot(&p.cast::<f64>().coords)).collect();
        trimmed_span(values, TRIM) / (1.0 - 2.0 * TRIM)
    };
    let millimetres = |value: f64| (value * 1000.0).round() / 1000.0;
    let size = TagSize { width: millimetres(extent(&across)), height: millimetres(extent(&along)) };
    (BOUNDS.contains(&size.width) && BOUNDS.contains(&size.height)).then_some(size)
}

/// How far `values` spread from their `trim` to their `1 - trim` quantile (interpolated):
/// their span without the strays at either end. Naught for no values.
pub(super) fn trimmed_span(mut values: Vec<f64>, trim: f64) -> f64 {
    let high = quantile(&mut values, 1.0 - trim);
    high - quantile(&mut values, trim)
}

/// The `q` quantile of `values`, interpolated between the two values about it, reordering
/// them (a selection, not a sort: this runs for every direction a part's width is measured
/// in). Naught for no values.
fn quantile(values: &mut [f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let position = q * (values.len() - 1) as f64;
    let below = position.floor() as usize;
    let (_, at, above) = values.select_nth_unstable_by(below, f64::total_cmp);
    let at = *at;
    match above.iter().copied().reduce(f64::min) {
        Some(next) => at + (next - at) * (position - below as f64),
        None => at,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Rotation3, Translation3};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A 5 × 8 cm patch on a surface leaning back 25° and turned 35° from the robot, 1.2 m
    /// away: its points 2 mm apart with 2 mm of depth noise, and `strays` specks of red up to
    /// 15 cm off its edges.
    fn patch_on_a_tilted_surface(seed: u64, strays: usize) -> (Vec<Point3<f32>>, Vector3<f64>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        // The surface's own frame: x across (level), y up along the surface, z its normal.
        let pose = Translation3::new(1.2, 0.1, 0.9)
            * Rotation3::from_axis_angle(&Vector3::z_axis(), 35f64.to_radians())
            * Rotation3::from_axis_angle(&Vector3::y_axis(), -90f64.to_radians())
            * Rotation3::from_axis_angle(&Vector3::z_axis(), -90f64.to_radians())
            * Rotation3::from_axis_angle(&Vector3::x_axis(), -25f64.to_radians());
        let normal = pose * Vector3::z();
        let mut members = Vec::new();
        for i in 0..25 {
            for j in 0..40 {
                let x = -0.025 + 0.001 + 0.002 * f64::from(i) + rng.random_range(-0.0005..0.0005);
                let y = -0.04 + 0.001 + 0.002 * f64::from(j) + rng.random_range(-0.0005..0.0005);
                let z = rng.random_range(-0.002..0.002);
                members.push((pose * Point3::new(x, y, z)).cast());
            }
        }
        for _ in 0..strays {
            let x = rng.random_range(0.03..0.15) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let y = rng.random_range(-0.15..0.15);
            members.push((pose * Point3::new(x, y, 0.0)).cast());
        }
        (members, normal)
    }

    #[test]
    fn a_five_by_eight_patch_on_a_tilted_surface_measures_five_by_eight() {
        let (members, normal) = patch_on_a_tilted_surface(1, 0);
        assert!(normal.z.abs() > 0.3, "the surface leans: {normal}");
        for seed in 0..100 {
            let (members, normal) = patch_on_a_tilted_surface(seed, 8);
            let size = extent_on(&members, &normal).unwrap();
            assert!((size.width - 0.05).abs() <= 0.002, "seed {seed}: {size:?}");
            assert!((size.height - 0.08).abs() <= 0.002, "seed {seed}: {size:?}");
        }
        // The normal's sign does not matter: the width is the level side either way.
        let size = extent_on(&members, &-normal).unwrap();
        assert!((size.width - 0.05).abs() <= 0.002 && (size.height - 0.08).abs() <= 0.002);
    }

    #[test]
    fn too_few_points_or_no_tag_s_size_measure_nothing() {
        let (members, normal) = patch_on_a_tilted_surface(3, 0);
        assert_eq!(extent_on(&members[..MIN_POINTS - 1], &normal), None);
        let line: Vec<Point3<f32>> =
            (0..200).map(|i| Point3::new(1.0, 0.0, i as f32 * 1e-5)).collect();
        assert_eq!(extent_on(&line, &-Vector3::x()), None, "2 mm tall is no tag");
    }
}
