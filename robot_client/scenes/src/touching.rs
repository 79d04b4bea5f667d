//! Scenes where something red-looking touches the tag, so that the tag is one part of a larger
//! red region (issue 34): a drawer cabinet of orange-brown plywood whose fronts pass the factory
//! colour thresholds in part, and a red plastic storage bin standing against the front with its
//! side touching the towel.
//!
//! Both start from a drawer scene of the corpus and change only what the issue names, so that a
//! miss here is the touching thing's doing.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::corpus::{DrawnScene, draw};
use crate::devices::{DeviceKind, DeviceParameters};
use crate::geometry::Shape;
use crate::materials::Material;
use crate::scene::Primitive;
use crate::{GeneratedScene, MIN_TAG_PIXELS, MIN_TAG_POINTS, render};

/// Orange-brown plywood as a real capture measured it (hue 14–24°, saturation 0.45–0.86, value
/// 0.3–0.6 in the camera): linear albedos whose sRGB hue is 13–22° and saturation 0.69–0.74
/// under white light, a light lacquer on the lighter ones.
pub const PLYWOOD: [Material; 3] = [
    Material::matte([0.30, 0.065, 0.02]),
    Material::shiny([0.38, 0.11, 0.035], 0.05, 15.0),
    Material::matte([0.25, 0.045, 0.02]),
];

/// Red polypropylene of a storage bin: about as red as the towel, and glossy.
pub const RED_PLASTIC: Material = Material::shiny([0.55, 0.035, 0.04], 0.2, 40.0).red_distractor();

/// What touches the tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Touching {
    /// The cabinet, its fronts included, is plywood.
    PlywoodCabinet,
    /// A red bin stands on the floor against the fronts, its side touching the towel.
    RedBin,
}

/// Drawer scene `seed` with `touching` added, rendered; redrawn like the corpus when the tag
/// is not in plain sight.
pub fn touching_scene(seed: u64, touching: Touching) -> GeneratedScene {
    let mut redraw = 0;
    loop {
        let scene = render(with_touching(draw(seed, Some(DeviceKind::Drawer), redraw), touching));
        let v = scene.visibility;
        if (v.tag_points >= MIN_TAG_POINTS && v.tag_pixels >= MIN_TAG_PIXELS) || redraw >= 20 {
            return scene;
        }
        redraw += 1;
    }
}

/// The drawn drawer scene with `touching` added.
pub fn with_touching(mut drawn: DrawnScene, touching: Touching) -> DrawnScene {
    let DeviceParameters::Drawer(drawer) = drawn.parameters.device else {
        return drawn;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(drawn.parameters.seed ^ 0x7001);
    match touching {
        Touching::PlywoodCabinet => {
            let wood =
                PLYWOOD[rng.random_range(0..PLYWOOD.len())].scaled(rng.random_range(0.9..1.1));
            for p in &mut drawn.scene.primitives {
                let cabinet = ["drawer front", "cabinet", "plinth"]
                    .iter()
                    .any(|part| p.name.starts_with(part));
                if cabinet {
                    p.material = wood;
                }
            }
        }
        Touching::RedBin => {
            let truth = drawn.truth;
            let normal = Vector3::from(truth.backing_normal);
            let normal = Vector3::new(normal.x, normal.y, 0.0).normalize();
            let across = Vector3::z().cross(&normal).normalize();
            let side = if rng.random_bool(0.5) { across } else { -across };
            let (width, depth) = (rng.random_range(0.3..0.45), rng.random_range(0.25..0.4));
            let tag = Point3::from(truth.tag_center);
            let foot = Point3::from(truth.backing_foot);
            // Against the front, its near side on the towel's edge, its rim at the towel's middle.
            let height = tag.z;
            let centre = foot
                + side * (drawer.towel_width_m / 2.0 + width / 2.0)
                + normal * (depth / 2.0)
                + Vector3::z() * (height / 2.0 - foot.z);
            // A box is its own mirror image: the turn needs the right-handed axes alone.
            let turn = UnitQuaternion::from_basis_unchecked(&[normal, across, Vector3::z()]);
            drawn.scene.primitives.push(Primitive::new(
                "red storage bin",
                Shape::Box { half_extents: [depth / 2.0, width / 2.0, height / 2.0] },
                Isometry3::from_parts(Translation3::from(centre.coords), turn),
                RED_PLASTIC,
            ));
        }
    }
    drawn
}
