//! The depth half of an RGB-D camera (RealSense D435's active stereo, Kinect-style structured
//! light), aligned to the colour image as their drivers publish it: one 16-bit millimetre depth
//! per colour pixel, measured on the very surfaces the colour pixels show. What such sensors get
//! wrong, from how they measure rather than from a noise term added at the end:
//!
//! - depth comes from disparity, `d = f·b/z`: matched with a σ of a fraction of a pixel and
//!   reported in sub-pixel steps, so the error grows with the square of the range and far depth
//!   comes in visible steps (quantised disparity);
//! - the second view (the other imager, or the projector) sits a baseline to one side, so the
//!   background beside a nearer edge is seen by one view only: no depth there (the occlusion
//!   band, as wide as the two surfaces' disparities differ);
//! - the matching window straddles depth edges: some pixels there come back between the two
//!   surfaces (flying pixels);
//! - dark surfaces return too little light to match, and a glossy one facing the sensor is
//!   blinded by its own highlight of the projector: holes;
//! - nothing nearer than the minimum range or beyond the maximum.

use pps_robot::perception::{DepthImage, DepthNoise};
use serde::{Deserialize, Serialize};

use crate::camera::PixelSurface;
use crate::caster::RayCaster;
use crate::noise::NoiseSource;

/// How the sensor finds depth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DepthTechnique {
    /// Two infrared imagers and a texture projector (RealSense D4xx, OAK-D Pro).
    ActiveStereo,
    /// One infrared imager and a known projected pattern (Kinect v1, Astra, Structure).
    StructuredLight,
}

/// An RGB-D camera's depth measurement.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DepthSensorModel {
    pub technique: DepthTechnique,
    /// Between the two views, metres.
    pub baseline_m: f64,
    /// Whether the second view sits to the right of the colour camera (+x, optical frame).
    pub second_view_right: bool,
    /// Focal length of the imager the disparity is matched in, pixels.
    pub depth_focal_px: f64,
    /// σ of the disparity match, pixels of that imager.
    pub disparity_sigma_px: f64,
    /// The disparity's reporting step, pixels (1/8 for Kinect v1, finer for a D435's subpixel).
    pub disparity_step_px: f64,
    pub min_range_m: f64,
    pub max_range_m: f64,
    /// Chance that a pixel beside a depth edge comes back between its two surfaces.
    pub flying_pixel_chance: f64,
    /// Mean reflectance below which matching starts to fail.
    pub dark_below: f64,
    /// Specular strength from which a surface facing the sensor within `glare_deg` is blinded.
    pub glare_specular: f64,
    pub glare_deg: f64,
}

/// A neighbour nearer or farther than this, metres, is another surface.
const DEPTH_EDGE_M: f64 = 0.04;

impl DepthSensorModel {
    /// σ of the depth at `z` metres: `z²·σ_d / (f·b)`.
    pub fn depth_sigma(&self, z: f64) -> f64 {
        z * z * self.disparity_sigma_px / (self.depth_focal_px * self.baseline_m)
    }

    /// The noise model a robot with this camera is given: its datasheet's focal length,
    /// baseline and disparity error, the reporting step's rounding included.
    pub fn noise(&self) -> DepthNoise {
        let step = self.disparity_step_px;
        let disparity_sigma = self.disparity_sigma_px.hypot(step / 12f64.sqrt());
        DepthNoise::disparity(self.depth_focal_px, self.baseline_m, disparity_sigma)
    }

    /// The depth image of the surfaces a colour camera of focal length `colour_fx` pixels saw,
    /// `width` pixels a row, drawing every flaw from `noise`.
    pub fn measure(
        &self,
        surfaces: &[Option<PixelSurface>],
        width: usize,
        colour_fx: f64,
        caster: &RayCaster,
        noise: &mut NoiseSource,
    ) -> Vec<u16> {
        let height = surfaces.len() / width;
        let mut z: Vec<f64> = surfaces.iter().map(|s| s.map_or(f64::NAN, |s| s.z)).collect();
        self.occlusion_band(&mut z, width, colour_fx);
        let edges = z.clone();
        let mut out = vec![0u16; z.len()];
        let focal_baseline = self.depth_focal_px * self.baseline_m;
        for y in 0..height {
            for x in 0..width {
                let i = y * width + x;
                let (Some(surface), true) = (surfaces[i], edges[i].is_finite()) else { continue };
                let material = caster.material(surface.primitive);
                let mut depth = edges[i];
                let neighbours = [
                    (x > 0).then(|| edges[i - 1]),
                    (x + 1 < width).then(|| edges[i + 1]),
                    (y > 0).then(|| edges[i - width]),
                    (y + 1 < height).then(|| edges[i + width]),
                ];
                let other = neighbours
                    .into_iter()
                    .flatten()
                    .find(|n| n.is_finite() && (n - depth).abs() > DEPTH_EDGE_M);
                if let Some(other) = other
                    && noise.chance(self.flying_pixel_chance)
                {
                    depth += (other - depth) * noise.between(0.2, 0.8);
                }
                let dark = ((self.dark_below - material.reflectance()) / self.dark_below).max(0.0);
                let glare = material.specular >= self.glare_specular
                    && surface.facing > self.glare_deg.to_radians().cos();
                let grazing = ((75f64.to_radians().cos() - surface.facing) / 0.26).max(0.0);
                if glare || noise.chance(0.9 * dark + grazing) {
                    continue;
                }
                let disparity = focal_baseline / depth + self.disparity_sigma_px * noise.normal();
                let reported =
                    (disparity / self.disparity_step_px).round() * self.disparity_step_px;
                if reported <= 0.0 {
                    continue;
                }
                let measured = focal_baseline / reported;
                if measured < self.min_range_m || measured > self.max_range_m {
                    continue;
                }
                out[i] = (measured * 1000.0).round().min(f64::from(u16::MAX)) as u16;
            }
        }
        out
    }

    /// Clears the depths the second view cannot see: a pixel whose point, seen from the second
    /// view, lies behind a nearer point of the same row. In colour pixels the second view sees
    /// pixel `u` at `u ∓ D(u)`, `D = f·b/z`; a nearer surface on the second view's side that
    /// lands at or past it there hides it.
    fn occlusion_band(&self, z: &mut [f64], width: usize, colour_fx: f64) {
        let shift = |u: usize, depth: f64| {
            let d = colour_fx * self.baseline_m / depth;
            if self.second_view_right { u as f64 - d } else { -(u as f64 + d) }
        };
        for row in z.chunks_mut(width) {
            // Scanning from the second view's side, the smallest landing seen so far.
            let mut nearest_landing = f64::INFINITY;
            let order: Box<dyn Iterator<Item = usize>> = if self.second_view_right {
                Box::new((0..width).rev())
            } else {
                Box::new(0..width)
            };
            for u in order {
                if !row[u].is_finite() {
                    continue;
                }
                let landing = shift(u, row[u]);
                if landing > nearest_landing {
                    row[u] = f64::NAN;
                } else {
                    nearest_landing = nearest_landing.min(landing);
                }
            }
        }
    }
}

/// The depth image `measure` gives, as the robot's perception reads it.
pub fn depth_image(width: u32, height: u32, millimetres: &[u16]) -> DepthImage {
    DepthImage::from_millimetres(width, height, millimetres)
        .expect("the sensor measures one depth per colour pixel")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(right: bool) -> DepthSensorModel {
        DepthSensorModel {
            technique: DepthTechnique::ActiveStereo,
            baseline_m: 0.05,
            second_view_right: right,
            depth_focal_px: 600.0,
            disparity_sigma_px: 0.08,
            disparity_step_px: 1.0 / 32.0,
            min_range_m: 0.3,
            max_range_m: 8.0,
            flying_pixel_chance: 0.3,
            dark_below: 0.05,
            glare_specular: 0.3,
            glare_deg: 10.0,
        }
    }

    #[test]
    fn the_depth_error_grows_with_the_square_of_the_range() {
        let m = model(true);
        assert!((m.depth_sigma(4.0) / m.depth_sigma(1.0) - 16.0).abs() < 1e-9);
        // A D435 at 2 m: about a centimetre.
        assert!((m.depth_sigma(2.0) - 0.0107).abs() < 0.001, "{}", m.depth_sigma(2.0));
    }

    #[test]
    fn the_background_beside_a_nearer_edge_is_a_hole_on_the_second_views_side() {
        // A row: background at 2 m, a post at 1 m on pixels 40..60.
        let row: Vec<f64> =
            (0..100).map(|u| if (40..60).contains(&u) { 1.0 } else { 2.0 }).collect();
        // Disparity difference in colour pixels: 600·0.05·(1/1 − 1/2) = 15, less the pixel
        // whose second-view ray grazes the post's edge.
        for right in [true, false] {
            let mut z = row.clone();
            model(right).occlusion_band(&mut z, 100, 600.0);
            let holes: Vec<usize> = (0..100).filter(|&u| z[u].is_nan()).collect();
            let expected: Vec<usize> = if right { (26..40).collect() } else { (60..74).collect() };
            assert_eq!(holes, expected, "second view right: {right}");
        }
    }
}
