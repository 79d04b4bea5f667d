//! The camera: the tag's colour under bright and dim light with the flash, and nothing else
//! red under any light.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pps_robot::perception::HsvThresholds;
use pps_scenes::camera::CameraModel;
use pps_scenes::caster::RayCaster;
use pps_scenes::geometry::Shape;
use pps_scenes::lighting::Lighting;
use pps_scenes::lighting::{Lights, PointLight};
use pps_scenes::materials::{self, Material};
use pps_scenes::noise::NoiseSource;
use pps_scenes::scene::{Pose, Primitive, Scene};

use super::wall;

/// A flash-lit wall 1 m ahead carrying a 30 cm square of `tag`, under `lighting`.
fn tag_scene(tag: Material, lighting: Lighting) -> Scene {
    let patch = Primitive::new(
        "patch",
        Shape::Box { half_extents: [0.004, 0.15, 0.15] },
        Isometry3::translation(0.996, 0.0, 1.2),
        tag,
    );
    let warm = [1.0, 0.78, 0.5];
    let (ambient, room) = match lighting {
        Lighting::Bright => (0.15, 3.0),
        Lighting::Dim => (0.005, 0.0),
    };
    Scene {
        primitives: vec![wall(1.0, 0.0), patch],
        lights: Lights {
            ambient: warm.map(|c| c * ambient),
            room: vec![PointLight {
                position: [0.6, -0.8, 2.5],
                intensity: warm.map(|c| c * room),
            }],
            flash: Some(PointLight { position: [0.0, 0.0, 1.24], intensity: [0.8; 3] }),
        },
    }
}

fn camera_at_one_metre(bias: f64, white_balance: [f64; 3]) -> CameraModel {
    // Level, looking along +x: optical z = x, optical x = −y, optical y = −z.
    let rotation =
        UnitQuaternion::from_basis_unchecked(&[-Vector3::y(), -Vector3::z(), Vector3::x()]);
    CameraModel {
        width: 640,
        height: 480,
        fx: 520.0,
        fy: 520.0,
        cx: 320.0,
        cy: 240.0,
        pose: Pose::from_isometry(&Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 1.2),
            rotation,
        )),
        exposure_bias_ev: bias,
        white_balance,
        vignetting: 0.9,
        // The noisiest sensor the corpus draws.
        read_noise: 0.002,
        shot_noise: 0.001,
    }
}

#[test]
fn the_tag_is_red_enough_in_bright_and_dim_light_with_the_flash() {
    let red = HsvThresholds::default();
    for tag in [materials::RED_TOWEL, materials::RED_FOAM, materials::RED_DYCEM] {
        for lighting in [Lighting::Bright, Lighting::Dim] {
            for (bias, balance) in [(-0.5, [0.95, 1.0, 1.05]), (0.5, [1.05, 1.0, 0.95])] {
                let scene = tag_scene(tag.scaled(0.85), lighting);
                let caster = RayCaster::new(&scene);
                let camera = camera_at_one_metre(bias, balance);
                let picture = camera.render(&scene, &caster, &mut NoiseSource::new(2, 3));
                // The tag covers ±78 px about the centre; look at its middle 60 × 60: its mean
                // colour is red, and noise flips few pixels (morphology mends those).
                let (mut passing, mut sum) = (0, [0u32; 3]);
                for y in 210..270 {
                    for x in 290..350 {
                        let px = picture.image.pixel(x, y);
                        passing += usize::from(red.contains(px));
                        (0..3).for_each(|c| sum[c] += u32::from(px[c]));
                    }
                }
                let mean = sum.map(|c| (c / 3600) as u8);
                assert!(
                    red.contains(mean) && passing >= 3600 * 95 / 100,
                    "{tag:?} {lighting:?} bias {bias}: mean {mean:?}, {passing} of 3600 pass"
                );
                assert!(!red.contains(picture.image.pixel(40, 240)), "the wall is not red");
            }
        }
    }
}

#[test]
fn nothing_but_the_red_things_is_red_under_any_light() {
    let red = HsvThresholds::default();
    let palettes: Vec<Material> = [
        &materials::WALLS[..],
        &materials::FURNITURE,
        &materials::FLOORS,
        &materials::CANS,
        &materials::PLASTICS,
        &materials::SHADES,
        &materials::CLUTTER,
        &[materials::CHROME, materials::BLACK_METAL],
    ]
    .concat();
    let lights = [[1.0, 0.78, 0.5], [1.0, 0.97, 0.92], [1.0, 0.98, 0.95]];
    for m in &palettes {
        for light in lights {
            for balance in [[1.05, 1.0, 0.95], [0.95, 1.0, 1.05]] {
                for exposure in [0.3, 0.6, 1.0, 1.6, 2.5] {
                    let rgb: [u8; 3] = std::array::from_fn(|c| {
                        pps_scenes::camera::linear_to_srgb8(
                            m.albedo[c] * light[c] * balance[c] * exposure,
                        )
                    });
                    assert!(!red.contains(rgb), "{m:?} under {light:?} reads red: {rgb:?}");
                }
            }
        }
    }
    for m in [materials::RED_BOOK, materials::RED_MUG, materials::RED_CUSHION] {
        let rgb: [u8; 3] =
            std::array::from_fn(|c| pps_scenes::camera::linear_to_srgb8(m.albedo[c] * 0.5));
        assert!(red.contains(rgb), "a distractor must look like a tag: {rgb:?}");
    }
}
