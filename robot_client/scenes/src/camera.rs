//! The colour camera: an exact pinhole (the calibration handed to perception is the one used
//! here, no distortion it does not model), one ray per pixel centre, then what a real camera
//! does to the light: vignetting, a white balance set for a light the room may not have,
//! metered exposure with a bias, signal-dependent (shot) and read noise, the sRGB curve and 8
//! bits.

use nalgebra::{Matrix3, Point3, Vector3};
use pps_robot::hal::{CameraCalibration, CameraIntrinsics, ColorImage};
use serde::{Deserialize, Serialize};

use crate::caster::RayCaster;
use crate::geometry::Ray;
use crate::noise::NoiseSource;
use crate::scene::{Pose, Scene};

/// Pixels on a tile's side: rays of one tile share one cull.
const TILE: usize = 16;
/// Linear values the sRGB table is sampled at.
const SRGB_STEPS: usize = 8192;
/// Farthest surface the camera renders, metres (beyond it, black).
const FAR: f64 = 20.0;

/// A camera and what it does to light.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CameraModel {
    pub width: u32,
    pub height: u32,
    /// Focal lengths and principal point, pixels.
    pub fx: f64,
    pub fy: f64,
    pub cx: f64,
    pub cy: f64,
    /// Base frame from the optical frame (z out of the lens, x right, y down).
    pub pose: Pose,
    /// Stops added to the metered exposure (negative: darker).
    pub exposure_bias_ev: f64,
    /// Per-channel gains of the white balance; 1 each for light the camera is balanced for.
    pub white_balance: [f64; 3],
    /// Strength of the cos⁴ fall-off toward the corners, 0 (none) to 1 (full).
    pub vignetting: f64,
    /// σ of the read noise, as a fraction of full scale (linear).
    pub read_noise: f64,
    /// Shot-noise variance per unit of linear signal.
    pub shot_noise: f64,
}

/// A rendered picture and how much of it the tag covers.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    pub image: ColorImage,
    /// Pixels whose ray first met the tag.
    pub tag_pixels: usize,
    /// The metered gain that mapped scene radiance to the sensor's full scale.
    pub gain: f64,
    /// What each pixel's ray met, row by row, when the render was asked for it (an RGB-D
    /// camera's depth is measured on the very surfaces the colour pixels show).
    pub surfaces: Vec<Option<PixelSurface>>,
}

/// The surface a pixel's ray first met.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelSurface {
    /// Depth along the optical axis, metres.
    pub z: f64,
    /// Cosine of the angle between the surface's normal and the ray back to the camera.
    pub facing: f64,
    pub primitive: u32,
}

impl CameraModel {
    /// Exactly the calibration the picture was rendered with.
    pub fn calibration(&self) -> CameraCalibration {
        CameraCalibration {
            intrinsics: CameraIntrinsics {
                width: self.width,
                height: self.height,
                fx: self.fx,
                fy: self.fy,
                cx: self.cx,
                cy: self.cy,
            },
            base_from_camera: self.pose.isometry(),
        }
    }

    /// The ray through the centre of pixel (x, y), in the optical frame (not normalised).
    fn pixel_direction(&self, x: f64, y: f64) -> Vector3<f64> {
        Vector3::new((x + 0.5 - self.cx) / self.fx, (y + 0.5 - self.cy) / self.fy, 1.0)
    }

    /// Renders the scene as this camera sees it, drawing the sensor's noise from `noise`.
    pub fn render(&self, scene: &Scene, caster: &RayCaster, noise: &mut NoiseSource) -> Picture {
        self.render_recording(scene, caster, noise, false)
    }

    /// Renders as [`Self::render`] does and also keeps what each pixel's ray met.
    pub fn render_with_surfaces(
        &self,
        scene: &Scene,
        caster: &RayCaster,
        noise: &mut NoiseSource,
    ) -> Picture {
        self.render_recording(scene, caster, noise, true)
    }

    fn render_recording(
        &self,
        scene: &Scene,
        caster: &RayCaster,
        noise: &mut NoiseSource,
        record: bool,
    ) -> Picture {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut surfaces = if record { vec![None; w * h] } else { Vec::new() };
        let iso = self.pose.isometry();
        let rotation: Matrix3<f64> = *iso.rotation.to_rotation_matrix().matrix();
        let eye = Point3::from(iso.translation.vector);
        let mut radiance = vec![[0f32; 3]; w * h];
        let mut tag_pixels = 0;
        let rects = self.screen_rects(caster);
        let mut candidates = Vec::new();
        for ty in (0..h).step_by(TILE) {
            for tx in (0..w).step_by(TILE) {
                let (x1, y1) = ((tx + TILE).min(w), (ty + TILE).min(h));
                candidates.clear();
                candidates.extend(rects.iter().filter_map(|&(i, [rx0, ry0, rx1, ry1])| {
                    (rx0 < x1 && tx < rx1 && ry0 < y1 && ty < ry1).then_some(i)
                }));
                for y in ty..y1 {
                    for x in tx..x1 {
                        let along = self.pixel_direction(x as f64, y as f64);
                        let ray = Ray::new(eye, rotation * along);
                        let Some(hit) = caster.cast(&ray, &candidates, FAR) else { continue };
                        if record {
                            // The ray's direction has z = 1 in the optical frame before it
                            // is normalised, so depth is the distance over its length.
                            surfaces[y * w + x] = Some(PixelSurface {
                                z: hit.t / along.norm(),
                                facing: hit.normal.dot(&-ray.direction),
                                primitive: hit.primitive,
                            });
                        }
                        let material = caster.material(hit.primitive);
                        tag_pixels += usize::from(material.is_tag);
                        let rgb =
                            scene.lights.shade(&hit.point, &hit.normal, &-ray.direction, material);
                        radiance[y * w + x] = rgb.map(|c| c as f32);
                    }
                }
            }
        }
        let gain = self.metered_gain(&radiance);
        let image = self.develop(&radiance, gain, noise);
        Picture { image, tag_pixels, gain, surfaces }
    }

    /// Each primitive's rectangle of pixels `[x0, y0, x1, y1)`, nearest first: where its bounding
    /// box projects, or the whole image when part of the box lies behind the lens.
    fn screen_rects(&self, caster: &RayCaster) -> Vec<(u32, [usize; 4])> {
        let (w, h) = (self.width as usize, self.height as usize);
        let base_from_camera = self.pose.isometry();
        let camera_from_base = base_from_camera.inverse();
        let eye = Point3::from(base_from_camera.translation.vector);
        let mut order: Vec<u32> = caster.all();
        order.sort_by(|&a, &b| {
            caster.sphere_distance(a, &eye).total_cmp(&caster.sphere_distance(b, &eye))
        });
        order
            .into_iter()
            .filter_map(|i| {
                let (mut u0, mut v0, mut u1, mut v1) =
                    (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
                for corner in caster.corners(i) {
                    let c = camera_from_base * corner;
                    if c.z < 0.02 {
                        return Some((i, [0, 0, w, h]));
                    }
                    let (u, v) = (self.fx * c.x / c.z + self.cx, self.fy * c.y / c.z + self.cy);
                    (u0, v0, u1, v1) = (u0.min(u), v0.min(v), u1.max(u), v1.max(v));
                }
                let clamp = |x: f64, n: usize| x.clamp(0.0, n as f64) as usize;
                let rect = [
                    clamp(u0.floor(), w),
                    clamp(v0.floor(), h),
                    clamp(u1.ceil() + 1.0, w),
                    clamp(v1.ceil() + 1.0, h),
                ];
                (rect[0] < rect[2] && rect[1] < rect[3]).then_some((i, rect))
            })
            .collect()
    }

    /// The gain that brings the centre-weighted mean luminance to mid grey (18 %), times the
    /// exposure bias, within the sensor's range of gains.
    fn metered_gain(&self, radiance: &[[f32; 3]]) -> f64 {
        let (w, h) = (self.width as usize, self.height as usize);
        let (mut sum, mut weight) = (0.0, 0.0);
        for y in (0..h).step_by(4) {
            for x in (0..w).step_by(4) {
                let [r, g, b] = radiance[y * w + x].map(f64::from);
                let (u, v) = (x as f64 / w as f64 - 0.5, y as f64 / h as f64 - 0.5);
                let k = (1.0 - 2.0 * (u * u + v * v)).max(0.1);
                sum += k * (0.2126 * r + 0.7152 * g + 0.0722 * b);
                weight += k;
            }
        }
        let mean = (sum / weight).max(1e-6);
        (0.18 / mean * 2f64.powf(self.exposure_bias_ev)).clamp(0.05, 40.0)
    }

    /// Radiance to 8-bit sRGB: gain, white balance, vignetting, noise, clipping, gamma.
    fn develop(&self, radiance: &[[f32; 3]], gain: f64, noise: &mut NoiseSource) -> ColorImage {
        let (w, h) = (self.width as usize, self.height as usize);
        let srgb = srgb_table();
        let mut image = ColorImage::new(self.width, self.height);
        let balance = self.white_balance.map(|c| (c * gain) as f32);
        let (read, shot) = (self.read_noise as f32, self.shot_noise as f32);
        for y in 0..h {
            let dy = (y as f64 + 0.5 - self.cy) / self.fy;
            for x in 0..w {
                let dx = (x as f64 + 0.5 - self.cx) / self.fx;
                let cos2 = 1.0 / (1.0 + dx * dx + dy * dy);
                let fall_off = (1.0 - self.vignetting + self.vignetting * cos2 * cos2) as f32;
                let i = y * w + x;
                for c in 0..3 {
                    let signal = radiance[i][c] * balance[c] * fall_off;
                    let sigma = (read * read + shot * signal.max(0.0)).sqrt();
                    let v = (signal + sigma * noise.quick_normal()).clamp(0.0, 1.0);
                    image.rgb[i * 3 + c] = srgb[(v * (SRGB_STEPS - 1) as f32 + 0.5) as usize];
                }
            }
        }
        image
    }
}

/// The sRGB transfer curve, linear 0..1 to 8 bits.
pub fn linear_to_srgb8(v: f64) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0).round() as u8
}

fn srgb_table() -> Vec<u8> {
    (0..SRGB_STEPS).map(|i| linear_to_srgb8(i as f64 / (SRGB_STEPS - 1) as f64)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_srgb_curve_meets_its_known_points() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        // 18 % grey is sRGB 118.
        assert_eq!(linear_to_srgb8(0.18), 118);
        assert_eq!(linear_to_srgb8(0.002), 7);
    }
}
