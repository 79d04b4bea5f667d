//! Common home materials that come near the tag's red, and what a camera makes of them under
//! warm and cool light: the data that says which colour thresholds keep a home's materials apart
//! from a tag ([`SEPARATING_COLOUR`]), and that the factory default does not.
//!
//! Each material is given as it was published (CIELAB, or sRGB where the source gives that),
//! with its source, and turned into a linear reflectance; [`rendered_hsv`] then lights it with a
//! black body of the illuminant's colour temperature and develops it as a camera with a white
//! balance fixed for daylight (the worst case: what the robot's camera does when nothing corrects
//! the cast) or with a full white balance. Nothing here is tuned: change a number only with its
//! source.

use pps_robot::perception::UNMISTAKABLE_HUES;
use pps_schema::ColorSegmentation;
use serde::Serialize;

/// The thresholds the table separates on: the tags' own materials reach hue 7.7° at most (warm
/// light, nothing corrected) and the nearest material that is not red, with saturation 0.6 or
/// more, starts at 12.3° (brick under 4000 K), so hue stops at 10°, midway. Saturation and
/// value are the factory's. The factory default ([`ColorSegmentation::default`], hue 340–20°)
/// is the published contract of `perceive` and stays; a household narrows it by learning its
/// tags' colour from confirmed reads, which converges on this side of the wood. Its hues are
/// perception's [`UNMISTAKABLE_HUES`]: a red region larger than any tag whose part nearest the
/// pointed location lies beyond them is searched for its points within them.
pub const SEPARATING_COLOUR: ColorSegmentation =
    ColorSegmentation { hue_deg: UNMISTAKABLE_HUES, saturation: [0.6, 1.0], value: [0.15, 1.0] };

/// How a material's colour was published.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Published {
    /// CIELAB (L*, a*, b*), read as adapted to its illuminant's white.
    Lab([f64; 3]),
    /// 8-bit sRGB under D65.
    Srgb([u8; 3]),
    /// Linear reflectance, as a renderer takes it.
    Linear([f64; 3]),
}

/// What a material is, in the groups the issue names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialGroup {
    Wood,
    Terracotta,
    Brick,
    Leather,
    Skin,
    /// Red plastics and fabrics: as red as a tag, told apart only by where they are.
    RedPlasticOrFabric,
    /// The tags' own materials, as the corpus and the simulator render them.
    Tag,
}

/// One row of the table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HomeMaterial {
    pub name: &'static str,
    pub group: MaterialGroup,
    pub published: Published,
    pub source: &'static str,
}

const CREWSICK: &str = "colorimetry of Australian pine and eucalypt woods, air dry, tangential \
                        face, illuminant A, 10° observer (Creswick School of Forestry collection)";
const COLORCHECKER: &str = "X-Rite ColorChecker Classic, published sRGB of the patch";
const TERRACOTTA: &str = "fired terracotta: L* 30–50, a* 10–25, b* 5–15 (a colour description, \
                          not a measurement: its corners)";
const CSS: &str =
    "CSS Color 4 named colour (a standard's name for the material, not a measurement)";
const CORPUS: &str = "the corpus's own tag material (materials.rs), linear reflectance";
const SIMULATOR: &str = "the simulator's tag material (pps-robot sim/room.rs), linear reflectance";

/// The table.
pub const HOME_MATERIALS: [HomeMaterial; 20] = [
    HomeMaterial {
        name: "maritime pine",
        group: MaterialGroup::Wood,
        published: Published::Lab([71.1, 19.3, 41.7]),
        source: CREWSICK,
    },
    HomeMaterial {
        name: "flooded gum",
        group: MaterialGroup::Wood,
        published: Published::Lab([61.6, 22.5, 31.4]),
        source: CREWSICK,
    },
    HomeMaterial {
        name: "red-brown eucalypt (E. propinqua)",
        group: MaterialGroup::Wood,
        published: Published::Lab([45.4, 23.9, 30.0]),
        source: CREWSICK,
    },
    HomeMaterial {
        name: "mountain grey gum (E. muelleriana)",
        group: MaterialGroup::Wood,
        published: Published::Lab([53.6, 14.0, 27.3]),
        source: CREWSICK,
    },
    HomeMaterial {
        name: "terracotta, light",
        group: MaterialGroup::Terracotta,
        published: Published::Lab([50.0, 25.0, 15.0]),
        source: TERRACOTTA,
    },
    HomeMaterial {
        name: "terracotta, dark",
        group: MaterialGroup::Terracotta,
        published: Published::Lab([30.0, 10.0, 5.0]),
        source: TERRACOTTA,
    },
    HomeMaterial {
        name: "brick red",
        group: MaterialGroup::Brick,
        published: Published::Lab([40.0, 25.0, 15.0]),
        source: TERRACOTTA,
    },
    HomeMaterial {
        name: "saddle brown leather",
        group: MaterialGroup::Leather,
        published: Published::Srgb([139, 69, 19]),
        source: CSS,
    },
    HomeMaterial {
        name: "sienna leather",
        group: MaterialGroup::Leather,
        published: Published::Srgb([160, 82, 45]),
        source: CSS,
    },
    HomeMaterial {
        name: "dark skin",
        group: MaterialGroup::Skin,
        published: Published::Srgb([115, 82, 68]),
        source: COLORCHECKER,
    },
    HomeMaterial {
        name: "light skin",
        group: MaterialGroup::Skin,
        published: Published::Srgb([194, 150, 130]),
        source: COLORCHECKER,
    },
    HomeMaterial {
        name: "red plastic",
        group: MaterialGroup::RedPlasticOrFabric,
        published: Published::Srgb([175, 54, 60]),
        source: COLORCHECKER,
    },
    HomeMaterial {
        name: "moderate red fabric",
        group: MaterialGroup::RedPlasticOrFabric,
        published: Published::Srgb([193, 90, 99]),
        source: COLORCHECKER,
    },
    HomeMaterial {
        name: "orange plastic",
        group: MaterialGroup::RedPlasticOrFabric,
        published: Published::Srgb([214, 126, 44]),
        source: COLORCHECKER,
    },
    HomeMaterial {
        name: "foam tube",
        group: MaterialGroup::Tag,
        published: Published::Linear([0.50, 0.035, 0.025]),
        source: CORPUS,
    },
    HomeMaterial {
        name: "Dycem patch",
        group: MaterialGroup::Tag,
        published: Published::Linear([0.55, 0.04, 0.035]),
        source: CORPUS,
    },
    HomeMaterial {
        name: "towel",
        group: MaterialGroup::Tag,
        published: Published::Linear([0.42, 0.03, 0.022]),
        source: CORPUS,
    },
    HomeMaterial {
        name: "simulator's foam tube",
        group: MaterialGroup::Tag,
        published: Published::Linear([0.55, 0.030, 0.035]),
        source: SIMULATOR,
    },
    HomeMaterial {
        name: "simulator's Dycem patch",
        group: MaterialGroup::Tag,
        published: Published::Linear([0.50, 0.025, 0.040]),
        source: SIMULATOR,
    },
    HomeMaterial {
        name: "simulator's towel",
        group: MaterialGroup::Tag,
        published: Published::Linear([0.45, 0.020, 0.030]),
        source: SIMULATOR,
    },
];

/// The light a scene is lit by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Illuminant {
    /// Incandescent and warm-white LED, 2700 K.
    Warm2700,
    /// Neutral-white LED and fluorescent, 4000 K.
    Neutral4000,
    /// Overcast daylight and cool-white LED, 6500 K.
    Cool6500,
}

impl Illuminant {
    pub const ALL: [Self; 3] = [Self::Warm2700, Self::Neutral4000, Self::Cool6500];

    pub fn kelvin(self) -> u32 {
        match self {
            Self::Warm2700 => 2700,
            Self::Neutral4000 => 4000,
            Self::Cool6500 => 6500,
        }
    }

    /// The black body's colour as linear sRGB relative to D65 white, red 1: from its sRGB
    /// (Mitchell Charity, "What color is a blackbody?", CIE 1931 2° observer: 2700 K
    /// #ffa957, 4000 K #ffd1a3, 6500 K #fff9fd).
    pub fn linear_rgb(self) -> [f64; 3] {
        let srgb: [u8; 3] = match self {
            Self::Warm2700 => [255, 169, 87],
            Self::Neutral4000 => [255, 209, 163],
            Self::Cool6500 => [255, 249, 253],
        };
        srgb.map(srgb8_to_linear)
    }
}

/// The sRGB curve's inverse: 8 bits to linear 0..1.
pub fn srgb8_to_linear(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.040_45 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

fn linear_to_srgb(v: f64) -> f64 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }
}

/// CIELAB under a white of D65 to linear sRGB (negative channels, outside the gamut, to 0).
pub fn lab_to_linear([l, a, b]: [f64; 3]) -> [f64; 3] {
    let fy = (l + 16.0) / 116.0;
    let (fx, fz) = (fy + a / 500.0, fy - b / 200.0);
    let f = |t: f64| if t.powi(3) > 0.008_856 { t.powi(3) } else { (t - 16.0 / 116.0) / 7.787 };
    let (x, y, z) = (0.950_47 * f(fx), f(fy), 1.088_83 * f(fz));
    [
        3.2406 * x - 1.5372 * y - 0.4986 * z,
        -0.9689 * x + 1.8758 * y + 0.0415 * z,
        0.0557 * x - 0.2040 * y + 1.0570 * z,
    ]
    .map(|c| c.max(0.0))
}

impl HomeMaterial {
    /// Linear sRGB reflectance. A CIELAB published under another illuminant is read as the
    /// colour a viewer adapted to that illuminant sees, and so as a reflectance under D65.
    pub fn reflectance(&self) -> [f64; 3] {
        match self.published {
            Published::Lab(lab) => lab_to_linear(lab),
            Published::Srgb(rgb) => rgb.map(srgb8_to_linear),
            Published::Linear(rgb) => rgb,
        }
    }
}

/// How the camera balances its colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum WhiteBalance {
    /// Fixed for daylight: the illuminant's cast stays in the picture.
    Daylight,
    /// Fully corrected: every illuminant looks like daylight.
    Corrected,
}

/// Hue (degrees, 0..360), saturation and value (0..1) of the material lit by `illuminant`,
/// developed with `balance` and exposed so that its brightest channel sits at `exposure`
/// (linear, 0..1). Hue and saturation hardly depend on the exposure (the sRGB curve is close
/// to a power); the value is the exposure's.
pub fn rendered_hsv(
    material: &HomeMaterial,
    illuminant: Illuminant,
    balance: WhiteBalance,
    exposure: f64,
) -> [f64; 3] {
    let [r, g, b] = rendered_srgb(material, illuminant, balance, exposure);
    let max = r.max(g).max(b);
    let chroma = max - r.min(g).min(b);
    let hue = if chroma <= 0.0 {
        0.0
    } else if max == r {
        60.0 * ((g - b) / chroma).rem_euclid(6.0)
    } else if max == g {
        60.0 * ((b - r) / chroma + 2.0)
    } else {
        60.0 * ((r - g) / chroma + 4.0)
    };
    let saturation = if max > 0.0 { chroma / max } else { 0.0 };
    [hue, saturation, max]
}

/// The 8-bit pixel [`rendered_hsv`] describes, as perception reads it.
pub fn rendered_pixel(
    material: &HomeMaterial,
    illuminant: Illuminant,
    balance: WhiteBalance,
    exposure: f64,
) -> [u8; 3] {
    rendered_srgb(material, illuminant, balance, exposure).map(|c| (c * 255.0).round() as u8)
}

fn rendered_srgb(
    material: &HomeMaterial,
    illuminant: Illuminant,
    balance: WhiteBalance,
    exposure: f64,
) -> [f64; 3] {
    let light = match balance {
        WhiteBalance::Daylight => illuminant.linear_rgb(),
        WhiteBalance::Corrected => [1.0; 3],
    };
    let r = material.reflectance();
    let lit = [r[0] * light[0], r[1] * light[1], r[2] * light[2]];
    let peak = lit.iter().copied().fold(f64::MIN, f64::max).max(1e-9);
    lit.map(|c| linear_to_srgb(c / peak * exposure))
}

#[cfg(test)]
mod tests {
    use pps_robot::perception::HsvThresholds;

    use super::*;

    /// Every lighting the table is rendered under.
    fn lightings() -> Vec<(Illuminant, WhiteBalance)> {
        Illuminant::ALL
            .into_iter()
            .flat_map(|i| [(i, WhiteBalance::Daylight), (i, WhiteBalance::Corrected)])
            .collect()
    }

    #[test]
    fn the_published_colours_come_back_through_the_conversions() {
        // The sRGB of ColorChecker's red, developed under daylight with a full balance.
        let red = HOME_MATERIALS.iter().find(|m| m.name == "red plastic").unwrap();
        let [h, s, v] = rendered_hsv(red, Illuminant::Cool6500, WhiteBalance::Corrected, 0.4287);
        assert!((h - 357.0).abs() < 0.2 && (s - 0.691).abs() < 0.005 && (v - 0.686).abs() < 0.005);
        // CIELAB of D65 white is linear 1, 1, 1.
        let white = lab_to_linear([100.0, 0.0, 0.0]);
        assert!(white.iter().all(|c| (c - 1.0).abs() < 2e-3), "{white:?}");
    }

    /// Whether `m` falls inside `thresholds` under every lighting, at a
    /// middle exposure (value is a matter of the light, not of the material).
    fn inside_under_every_light(thresholds: &HsvThresholds, m: &HomeMaterial) -> Vec<bool> {
        lightings()
            .into_iter()
            .map(|(illuminant, balance)| {
                thresholds.contains(rendered_pixel(m, illuminant, balance, 0.4))
            })
            .collect()
    }

    #[test]
    fn the_factory_default_lets_wood_leather_and_brick_in() {
        // Why a tag is a bounded thing and a household learns its colour: the contract's default
        // takes warm-lit wood, leather and brick for a tag.
        let factory = HsvThresholds::default();
        for name in ["red-brown eucalypt (E. propinqua)", "sienna leather", "brick red"] {
            let m = HOME_MATERIALS.iter().find(|m| m.name == name).unwrap();
            assert!(inside_under_every_light(&factory, m)[0], "{name} under 2700 K, daylight");
        }
    }

    #[test]
    fn the_separating_colour_lets_every_tag_in_and_keeps_every_home_material_out() {
        let defaults = HsvThresholds::new(&SEPARATING_COLOUR).unwrap();
        for m in &HOME_MATERIALS {
            // Red plastics and fabrics are as red as a tag: only where they are tells them apart.
            if m.group == MaterialGroup::RedPlasticOrFabric {
                continue;
            }
            for (illuminant, balance) in lightings() {
                // At a middle exposure: value is a matter of the light, not of the material.
                let [h, s, _] = rendered_hsv(m, illuminant, balance, 0.4);
                let inside = defaults.contains(rendered_pixel(m, illuminant, balance, 0.4));
                assert_eq!(
                    inside,
                    m.group == MaterialGroup::Tag,
                    "{} under {} K, {balance:?}: hue {h:.1}°, saturation {s:.2}",
                    m.name,
                    illuminant.kelvin()
                );
            }
        }
    }
}
