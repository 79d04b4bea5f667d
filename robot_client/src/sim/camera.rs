//! Rendering what the cameras see: one ray per pixel through the pinhole model, shaded by the
//! room's lights and the flash, with sensor noise.
//!
//! Shading is diffuse without shadows: enough for the colours and brightness changes that
//! perception relies on, and cheap enough to render a 1280×960 frame in well under a second.

use nalgebra::{Isometry3, Point3, Vector3};
use rand::Rng;

use super::noise::SensorNoise;
use super::room::Room;
use super::scene::{Hit, LightSource, Surface, linear_to_srgb};
use crate::hal::{CameraIntrinsics, ColorImage, GrayImage};

/// Which lights are on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lighting {
    pub ceiling_on: bool,
    pub lamp_on: bool,
}

impl Default for Lighting {
    /// Office lighting, as in the paper's trials: the ceiling light on, the lamp off.
    fn default() -> Self {
        Self { ceiling_on: true, lamp_on: false }
    }
}

/// The camera's light response.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exposure {
    /// Flash intensity: irradiance at 1 m on a surface facing it.
    pub flash_power: f32,
    /// Standard deviation of per-channel noise, in 0..1 sRGB units.
    pub noise: f32,
    /// The sensor's colour response: row `i` says how much of the scene's linear red, green and
    /// blue reaches the image's channel `i`. Cameras differ here (filter dyes, crosstalk, white
    /// balance), which is why a tag's HSV thresholds belong to a robot class, not to the tag.
    pub colour_response: [[f32; 3]; 3],
}

/// A sensor whose channels see only their own colour.
pub const TRUE_COLOUR: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Default for Exposure {
    fn default() -> Self {
        Self { flash_power: 1.4, noise: 0.008, colour_response: TRUE_COLOUR }
    }
}

impl Exposure {
    /// What the sensor's channels make of linear `radiance`.
    fn respond(&self, radiance: [f32; 3]) -> [f32; 3] {
        self.colour_response.map(|row| row.iter().zip(&radiance).map(|(w, c)| w * c).sum())
    }
}

/// Irradiance from a point light of `power` at `light` on a surface at `hit`.
fn point_light(hit: &Hit, light: &Point3<f32>, power: f32) -> f32 {
    let to_light = light - hit.point;
    let d2 = to_light.norm_squared().max(0.01);
    power * hit.normal.dot(&to_light).max(0.0) / (d2 * d2.sqrt())
}

/// Linear radiance leaving the surface at `hit` toward the camera.
fn shade(
    room: &Room,
    lighting: Lighting,
    hit: &Hit,
    flash: Option<(&Point3<f32>, f32)>,
) -> [f32; 3] {
    let mut irradiance = room.daylight;
    if lighting.ceiling_on {
        irradiance += 0.2 + point_light(hit, &room.ceiling_light, 2.0);
    }
    if lighting.lamp_on {
        irradiance += 0.05 + point_light(hit, &room.lamp_light, 0.6);
    }
    let mut highlight = 0.0;
    if let Some((origin, power)) = flash {
        let from_flash = point_light(hit, origin, power);
        irradiance += from_flash;
        if let Surface::Glossy { shine, .. } = room.scene.parts()[hit.part].surface {
            // The flash sits at the lens, so the mirror direction is straight back along the ray.
            let facing = hit.normal.dot(&(origin - hit.point).normalize()).max(0.0);
            highlight = shine * from_flash * facing.powi(60);
        }
    }
    let reflectance = room.scene.reflectance(hit);
    let glow = match room.scene.parts()[hit.part].surface {
        Surface::Glowing { source: LightSource::Ceiling, radiance, .. } if lighting.ceiling_on => {
            radiance
        }
        Surface::Glowing { source: LightSource::Lamp, radiance, .. } if lighting.lamp_on => {
            radiance
        }
        _ => 0.0,
    };
    reflectance.map(|r| r * irradiance + glow + highlight)
}

/// Renders the colour image a camera at `world_from_camera` (optical frame: z out of the lens,
/// x right, y down) sees.
pub fn render_color(
    room: &Room,
    lighting: Lighting,
    world_from_camera: &Isometry3<f64>,
    intrinsics: &CameraIntrinsics,
    flash: bool,
    exposure: &Exposure,
    rng: &mut impl Rng,
) -> ColorImage {
    let mut image = ColorImage::new(intrinsics.width, intrinsics.height);
    let pose: Isometry3<f32> = world_from_camera.cast();
    let origin = Point3::from(pose.translation.vector);
    let flash = flash.then_some((&origin, exposure.flash_power));
    let mut noise = SensorNoise::new(rng);
    let mut i = 0;
    for v in 0..intrinsics.height {
        for u in 0..intrinsics.width {
            let dir = pixel_ray(intrinsics, &pose, u, v);
            let radiance = room
                .scene
                .cast(&origin, &dir, 50.0)
                .map_or([0.0; 3], |hit| shade(room, lighting, &hit, flash));
            for c in exposure.respond(radiance) {
                let value =
                    linear_to_srgb(c.clamp(0.0, 1.0)) + exposure.noise * noise.gaussian() as f32;
                image.rgb[i] = (value * 255.0).round().clamp(0.0, 255.0) as u8;
                i += 1;
            }
        }
    }
    image
}

/// Renders a grey image (the brightness camera: no flash, coarse resolution).
pub fn render_gray(
    room: &Room,
    lighting: Lighting,
    world_from_camera: &Isometry3<f64>,
    intrinsics: &CameraIntrinsics,
    exposure: &Exposure,
    rng: &mut impl Rng,
) -> GrayImage {
    let color = render_color(room, lighting, world_from_camera, intrinsics, false, exposure, rng);
    let luma = color
        .rgb
        .chunks_exact(3)
        .map(|p| {
            (0.299 * f32::from(p[0]) + 0.587 * f32::from(p[1]) + 0.114 * f32::from(p[2])).round()
                as u8
        })
        .collect();
    GrayImage { width: color.width, height: color.height, luma }
}

/// World direction of the ray through the centre of pixel (u, v).
fn pixel_ray(k: &CameraIntrinsics, pose: &Isometry3<f32>, u: u32, v: u32) -> Vector3<f32> {
    let x = ((f64::from(u) + 0.5 - k.cx) / k.fx) as f32;
    let y = ((f64::from(v) + 0.5 - k.cy) / k.fy) as f32;
    (pose.rotation * Vector3::new(x, y, 1.0)).normalize()
}
