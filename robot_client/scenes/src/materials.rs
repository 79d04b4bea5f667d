//! Surface materials and the palettes scenes draw them from.
//!
//! Albedos are linear RGB reflectances (0..1), not sRGB: the camera applies the gamma. The reds
//! are chosen as measured reds are: a strong red channel, a little green and blue. Every other
//! palette stays out of the tag's colour range under every light a scene may have (warm evening
//! light included), so that a red pixel in a scene is always either the tag or a distractor
//! placed on purpose.

use serde::{Deserialize, Serialize};

/// How a surface reflects light, and what it is for the ground truth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Diffuse reflectance, linear RGB 0..1.
    pub albedo: [f64; 3],
    /// Strength of the specular highlight (0 for matte surfaces), and its Blinn–Phong exponent
    /// (used as a whole number).
    pub specular: f64,
    pub shininess: f64,
    /// Part of the PPS-tag.
    #[serde(default)]
    pub is_tag: bool,
    /// A red thing that is not the tag (a book, a mug, a cushion).
    #[serde(default)]
    pub is_red_distractor: bool,
}

impl Material {
    pub const fn matte(albedo: [f64; 3]) -> Self {
        Self { albedo, specular: 0.0, shininess: 1.0, is_tag: false, is_red_distractor: false }
    }

    pub const fn shiny(albedo: [f64; 3], specular: f64, shininess: f64) -> Self {
        Self { albedo, specular, shininess, is_tag: false, is_red_distractor: false }
    }

    /// The same surface marked as part of the tag.
    pub const fn tag(self) -> Self {
        Self { is_tag: true, ..self }
    }

    /// The same surface marked as a red distractor.
    pub const fn red_distractor(self) -> Self {
        Self { is_red_distractor: true, ..self }
    }

    /// The same surface with its albedo scaled by `factor` (a darker or lighter batch).
    pub fn scaled(self, factor: f64) -> Self {
        Self { albedo: self.albedo.map(|c| (c * factor).clamp(0.0, 1.0)), ..self }
    }

    /// Mean reflectance, which also sets how strongly the surface returns the laser.
    pub fn reflectance(&self) -> f64 {
        self.albedo.iter().sum::<f64>() / 3.0
    }
}

/// The tags' materials (paper §III-A): foam tube, Dycem patch, towel. Their hue sits a few
/// degrees on the orange side of pure red, as dyed reds do; a blue above the green would put
/// dim, noisy pixels across the magenta edge of the tag's hue range.
pub const RED_FOAM: Material = Material::matte([0.50, 0.035, 0.025]).tag();
pub const RED_DYCEM: Material = Material::shiny([0.55, 0.04, 0.035], 0.015, 30.0).tag();
pub const RED_TOWEL: Material = Material::matte([0.42, 0.03, 0.022]).tag();

/// Red things that are not tags.
pub const RED_BOOK: Material = Material::matte([0.45, 0.035, 0.03]).red_distractor();
pub const RED_MUG: Material = Material::shiny([0.52, 0.03, 0.028], 0.35, 60.0).red_distractor();
pub const RED_CUSHION: Material = Material::matte([0.40, 0.03, 0.03]).red_distractor();

/// Wall paints.
pub const WALLS: [Material; 6] = [
    Material::matte([0.80, 0.80, 0.78]),
    Material::matte([0.78, 0.74, 0.66]),
    Material::matte([0.60, 0.60, 0.60]),
    Material::matte([0.55, 0.62, 0.70]),
    Material::matte([0.58, 0.66, 0.55]),
    Material::matte([0.70, 0.64, 0.54]),
];

/// Cabinet and furniture finishes: gloss white, grey, light and dark wood, navy, sage.
pub const FURNITURE: [Material; 6] = [
    Material::shiny([0.82, 0.82, 0.80], 0.25, 60.0),
    Material::matte([0.45, 0.46, 0.48]),
    Material::shiny([0.55, 0.42, 0.28], 0.08, 20.0),
    Material::shiny([0.25, 0.15, 0.08], 0.10, 25.0),
    Material::matte([0.05, 0.07, 0.15]),
    Material::matte([0.40, 0.46, 0.38]),
];

/// Floors: oak, grey carpet, pale tile.
pub const FLOORS: [Material; 3] = [
    Material::shiny([0.36, 0.26, 0.16], 0.06, 15.0),
    Material::matte([0.30, 0.30, 0.32]),
    Material::shiny([0.62, 0.62, 0.60], 0.15, 40.0),
];

/// Trash cans: brushed steel, white, grey and beige plastic.
pub const CANS: [Material; 4] = [
    Material::shiny([0.55, 0.55, 0.56], 0.45, 30.0),
    Material::shiny([0.80, 0.80, 0.78], 0.15, 30.0),
    Material::matte([0.35, 0.36, 0.37]),
    Material::matte([0.68, 0.62, 0.50]),
];

/// Switch plates and toggles: white and ivory plastic.
pub const PLASTICS: [Material; 2] = [
    Material::shiny([0.80, 0.79, 0.75], 0.2, 40.0),
    Material::shiny([0.76, 0.70, 0.58], 0.2, 40.0),
];

/// Chrome, for lamp poles and bases, drawer handles and pull chains.
pub const CHROME: Material = Material::shiny([0.60, 0.60, 0.62], 0.6, 80.0);
/// Dark metal, the other common finish of the same.
pub const BLACK_METAL: Material = Material::shiny([0.04, 0.04, 0.045], 0.3, 40.0);
/// Fabric lamp shades.
pub const SHADES: [Material; 2] =
    [Material::matte([0.78, 0.74, 0.64]), Material::matte([0.85, 0.85, 0.83])];
/// The floor objects: a wicker basket, a blue bin, a grey box, a green plant pot.
pub const CLUTTER: [Material; 4] = [
    Material::matte([0.45, 0.36, 0.22]),
    Material::matte([0.10, 0.20, 0.45]),
    Material::matte([0.50, 0.50, 0.50]),
    Material::matte([0.20, 0.35, 0.22]),
];
