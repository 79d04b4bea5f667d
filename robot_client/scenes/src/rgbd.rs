//! What a scene seen by an RGB-D camera has that the laser corpus does not (issue 34): the
//! camera's own depth sensor (no flash, no separate laser), ranges of 0.5–5 m, warm 2700 K to
//! cool 6500 K light only partly corrected by the camera's white balance, wood-toned fronts and
//! furniture from the home-materials table, and red things touching or overlapping the tag.
//!
//! Drawn after everything the laser corpus draws, so that the laser corpus's scenes stay the
//! same draw for draw.

use nalgebra::{Isometry3, Translation3, Vector3};
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::depth_sensor::{DepthSensorModel, DepthTechnique};
use crate::devices::Device;
use crate::draw::Draw;
use crate::geometry::Shape;
use crate::home_materials::{HOME_MATERIALS, Illuminant, MaterialGroup};
use crate::lighting::{Lights, PointLight};
use crate::materials::{self, Material};
use crate::scene::Primitive;

/// Colour image sizes of RGB-D cameras: 0.3 to 0.9 megapixels.
pub(crate) const IMAGE_SIZES: [[u32; 2]; 4] = [[640, 480], [848, 480], [1024, 768], [1280, 720]];

/// Everything the RGB-D part of a scene was drawn with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RgbdParameters {
    pub sensor: DepthSensorModel,
    pub illuminant_k: u32,
    /// Share of the light's colour cast the camera's white balance takes out, 0..1.
    pub white_balance_correction: f64,
    /// The wood the furniture is made of, when it is.
    pub wood: Option<String>,
    /// Whether the wall behind the device is wood-panelled too.
    pub wooden_wall: bool,
    pub red_touching: Option<RedTouching>,
}

/// A red thing beside the tag, device frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RedTouching {
    pub material: String,
    /// How far it reaches under or over the tag's edge, metres (0: touching).
    pub overlap_m: f64,
    pub size_m: [f64; 3],
}

/// Which of the variants a scene may have.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RgbdVariants {
    /// Wood-toned fronts, furniture and walls.
    pub wood: bool,
    /// Red things touching or overlapping the tag.
    pub red_touching: bool,
    /// The farthest the camera stands from the tag, metres (from 0.5).
    pub farthest_m: f64,
}

impl RgbdVariants {
    /// Dense noisy frames at 0.5–5 m under warm to cool light.
    pub const PLAIN: Self = Self { wood: false, red_touching: false, farthest_m: 5.0 };
    /// The same from where a robot that has come to the target looks: 0.5–2.5 m.
    pub const NEAR: Self = Self { farthest_m: 2.5, ..Self::PLAIN };
    /// Wood in the furniture (and some walls), nothing red touching the tag: the real captures
    /// of issue 34 had a plywood wall behind the tag.
    pub const WOOD: Self = Self { wood: true, ..Self::PLAIN };
    /// Wood in the furniture and red things touching the tag as well.
    pub const HOMES: Self = Self { wood: true, red_touching: true, farthest_m: 5.0 };
}

/// Draws the depth sensor: a RealSense-like active stereo pair or a Kinect-like structured-light
/// camera, each with its published baseline, focal length and disparity step.
pub(crate) fn draw_sensor(d: &mut Draw) -> DepthSensorModel {
    if d.chance(0.6) {
        // D435: 50 mm baseline, 87° wide depth imager at 848 or 1280 pixels, ~0.08 px RMS
        // subpixel, disparity in 1/32 px.
        let width = if d.chance(0.5) { 848.0 } else { 1280.0 };
        DepthSensorModel {
            technique: DepthTechnique::ActiveStereo,
            baseline_m: 0.05,
            second_view_right: d.chance(0.5),
            depth_focal_px: width / 2.0 / 43.5f64.to_radians().tan(),
            disparity_sigma_px: d.u(0.05, 0.12),
            disparity_step_px: 1.0 / 32.0,
            min_range_m: 0.28,
            max_range_m: 10.0,
            flying_pixel_chance: d.u(0.1, 0.5),
            dark_below: d.u(0.03, 0.08),
            glare_specular: 0.3,
            glare_deg: d.u(5.0, 12.0),
        }
    } else {
        // Kinect v1: 75 mm from projector to imager, 580 px focal length, 1/8 px disparity.
        DepthSensorModel {
            technique: DepthTechnique::StructuredLight,
            baseline_m: 0.075,
            second_view_right: d.chance(0.5),
            depth_focal_px: 580.0,
            disparity_sigma_px: d.u(0.05, 0.1),
            disparity_step_px: 0.125,
            min_range_m: 0.45,
            max_range_m: 8.0,
            flying_pixel_chance: d.u(0.1, 0.5),
            dark_below: d.u(0.03, 0.08),
            glare_specular: 0.3,
            glare_deg: d.u(5.0, 12.0),
        }
    }
}

/// The room's light without a flash (RGB-D cameras have none): one illuminant for the ceiling
/// lights and the ambient, bright day to dim evening.
pub(crate) fn draw_lights(illuminant: Illuminant, ceiling: &[[f64; 3]], d: &mut Draw) -> Lights {
    let colour = illuminant.linear_rgb();
    let ambient = d.u(0.01, 0.15);
    let room = ceiling
        .iter()
        .map(|&position| {
            let power = d.u(0.5, 3.0);
            PointLight { position, intensity: colour.map(|c| c * power) }
        })
        .collect();
    Lights { ambient: colour.map(|c| c * ambient), room, flash: None }
}

/// The white balance gains that take `correction` of the illuminant's cast out (in stops).
pub(crate) fn white_balance(illuminant: Illuminant, correction: f64) -> [f64; 3] {
    let light = illuminant.linear_rgb();
    light.map(|c| (c / light[1]).powf(-correction))
}

/// A wood from the table as a varnished surface.
fn wood_material(d: &mut Draw) -> (String, Material) {
    let woods: Vec<_> = HOME_MATERIALS.iter().filter(|m| m.group == MaterialGroup::Wood).collect();
    let wood = woods[d.rng.random_range(0..woods.len())];
    let material = Material::shiny(wood.reflectance(), d.u(0.03, 0.1), 20.0).scaled(d.u(0.8, 1.1));
    (wood.name.to_string(), material)
}

/// Turns the furniture, cans and (sometimes) the wall of `primitives` to one wood.
pub(crate) fn make_wooden(
    primitives: &mut [Primitive],
    wall: &Material,
    d: &mut Draw,
) -> (String, bool) {
    let (name, wood) = wood_material(d);
    let wooden_wall = d.chance(0.3);
    for p in primitives.iter_mut() {
        let furniture =
            materials::FURNITURE.contains(&p.material) || materials::CANS.contains(&p.material);
        if furniture || (wooden_wall && p.material == *wall && p.name.contains("wall")) {
            p.material = wood;
        }
    }
    (name, wooden_wall)
}

/// A red slab beside the tag, on the surface the tag is on, touching its edge or reaching up to
/// 2 cm under or over it; device frame.
pub(crate) fn red_touching(device: &Device, d: &mut Draw) -> (RedTouching, Primitive) {
    let reds: Vec<_> =
        HOME_MATERIALS.iter().filter(|m| m.group == MaterialGroup::RedPlasticOrFabric).collect();
    let red = reds[d.rng.random_range(0..2.min(reds.len()))];
    let material = Material::matte(red.reflectance()).red_distractor();
    let tag = device.tag_extent;
    let thickness = d.u(0.005, tag.max.x - tag.min.x + 0.01);
    let (width, height) = (d.u(0.08, 0.3), d.u(0.08, 0.3));
    let overlap = if d.chance(0.5) { 0.0 } else { d.u(0.0, 0.02) };
    let side = d.sign();
    let y0 = if side > 0.0 { tag.max.y - overlap } else { tag.min.y + overlap - width };
    let z_mid = (tag.min.z + tag.max.z) / 2.0 + d.u(-height / 3.0, height / 3.0);
    let centre = Vector3::new(tag.min.x + thickness / 2.0, y0 + width / 2.0, z_mid);
    let primitive = Primitive::new(
        "red thing touching the tag",
        Shape::Box { half_extents: [thickness / 2.0, width / 2.0, height / 2.0] },
        Isometry3::from_parts(Translation3::from(centre), Default::default()),
        material,
    );
    let described = RedTouching {
        material: red.name.to_string(),
        overlap_m: overlap,
        size_m: [thickness, width, height],
    };
    (described, primitive)
}
