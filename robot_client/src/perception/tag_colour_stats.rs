//! The colour a detected tag had in the picture, for the trial (DESIGN §10): once the fingers
//! have read the tag's EPC, the pixels the tag search took for it are known to be that tag, and
//! the registry learns the tag's colour, and the household's, from them.
//!
//! The pixels are those the tag's own laser points land on that have the colour of its middle:
//! every one passed the thresholds the search used, and wood grain or a fringe that the search
//! joined to the tag (a region the size of a tag is not divided) is left out, so that the
//! registry never learns the wood as the tag's colour.

use pps_schema::TagColor;

use super::bounded_tag::of_the_colour_at;
use super::hsv::hsv_of;
use super::tag_search_params::TagSearchParams;
use super::tag_sighting::TagDetection;
use crate::hal::{CameraCalibration, ColorImage};

/// Every this many pixels of the picture, in both directions, tell its light level: a
/// 1280×960 picture is then 4,800 samples, a median's error far below the value's 1/255 steps.
const LIGHT_SAMPLE_STEP: usize = 16;

/// The statistics of the pixels the tag's points land on that have the colour of its middle;
/// `None` when none lands in the picture.
pub fn tag_color(
    image: &ColorImage,
    calibration: &CameraCalibration,
    tag: &TagDetection,
    params: &TagSearchParams,
) -> Option<TagColor> {
    let members = of_the_colour_at(&tag.members, image, calibration, &tag.centroid, params);
    let camera_from_base = calibration.base_from_camera.inverse();
    let k = &calibration.intrinsics;
    let mut pixels: Vec<(u32, u32)> = members
        .iter()
        .filter_map(|p| {
            let uv = k.project(&(camera_from_base * p.cast::<f64>()))?;
            let inside = uv.x >= 0.0
                && uv.y >= 0.0
                && uv.x < f64::from(image.width)
                && uv.y < f64::from(image.height);
            inside.then_some((uv.x as u32, uv.y as u32))
        })
        .collect();
    // A pixel several points land on counts once.
    pixels.sort_unstable();
    pixels.dedup();
    if pixels.is_empty() {
        return None;
    }
    let hsv: Vec<[f32; 3]> = pixels.iter().map(|&(x, y)| hsv_of(image.pixel(x, y))).collect();
    Some(TagColor {
        pixels: pixels.len() as u64,
        hue_deg: hue_percentiles(hsv.iter().map(|c| c[0]).collect()),
        saturation: percentiles(hsv.iter().map(|c| c[1]).collect()),
        value: percentiles(hsv.iter().map(|c| c[2]).collect()),
        light_level: light_level(image),
    })
}

/// The 5th, 50th and 95th percentiles of `values`, which must not be empty.
fn percentiles(mut values: Vec<f32>) -> [f64; 3] {
    values.sort_by(f32::total_cmp);
    let at = |q: f64| {
        let i = ((values.len() - 1) as f64 * q).round() as usize;
        f64::from(values[i])
    };
    [at(0.05), at(0.5), at(0.95)]
}

/// Percentiles of hues (degrees) along the circle, cut opposite their mean direction so that
/// the reds either side of 0° stay together; back in 0..360.
fn hue_percentiles(hues: Vec<f32>) -> [f64; 3] {
    let (sin, cos) = hues.iter().fold((0.0f32, 0.0f32), |(s, c), h| {
        let (hs, hc) = h.to_radians().sin_cos();
        (s + hs, c + hc)
    });
    let middle = sin.atan2(cos).to_degrees();
    let unwrapped: Vec<f32> =
        hues.iter().map(|h| middle + (h - middle + 180.0).rem_euclid(360.0) - 180.0).collect();
    percentiles(unwrapped).map(|h| h.rem_euclid(360.0))
}

/// The median value of the picture, sampled every `LIGHT_SAMPLE_STEP` pixels.
fn light_level(image: &ColorImage) -> f64 {
    let values: Vec<f32> = (0..image.height as usize)
        .step_by(LIGHT_SAMPLE_STEP)
        .flat_map(|y| {
            (0..image.width as usize)
                .step_by(LIGHT_SAMPLE_STEP)
                .map(move |x| hsv_of(image.pixel(x as u32, y as u32))[2])
        })
        .collect();
    if values.is_empty() { 0.0 } else { percentiles(values)[1] }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hues_either_side_of_red_stay_together() {
        let hues: Vec<f32> = (0..100).map(|i| (350.0 + i as f32 * 0.2).rem_euclid(360.0)).collect();
        let [low, middle, high] = hue_percentiles(hues);
        assert!((low - 351.0).abs() < 0.3, "{low}");
        assert!((middle - 0.0).abs() < 0.3 || (middle - 360.0).abs() < 0.3, "{middle}");
        assert!((high - 8.8).abs() < 0.3, "{high}");
        assert_eq!(percentiles(vec![0.3, 0.1, 0.2]), [0.1f32, 0.2, 0.3].map(f64::from));
    }
}
