//! The two light switches: the flip switch with a foam tube on its toggle, and the ADA rocker
//! with a Dycem patch on the rocker and its plate.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::Rng;

use super::parts::{extent_of, pick, rod, slab};
use super::{Device, FlipSwitch, Rocker};
use crate::geometry::Shape;
use crate::materials;
use crate::scene::Primitive;

/// Switch plates are 7 × 11.4 cm and 6 mm thick.
const PLATE: [f64; 3] = [0.006, 0.035, 0.057];

pub(super) fn flip_switch(s: &FlipSwitch, rng: &mut impl Rng) -> Device {
    let plastic = pick(&materials::PLASTICS, rng);
    let z = s.plate_height_m;
    let plate = slab(
        "switch plate",
        [0.0, -PLATE[1], z - PLATE[2]],
        [PLATE[0], PLATE[1], z + PLATE[2]],
        plastic,
    );
    // The toggle leaves the plate tilted 15–25° up or down; the tube slides over it.
    let tilt = rng.random_range(15f64..25.0).to_radians() * if s.toggle_up { 1.0 } else { -1.0 };
    let axis = Vector3::new(tilt.cos(), 0.0, tilt.sin());
    let root = Point3::new(PLATE[0], 0.0, z);
    let lever = rod("toggle", root + axis * 0.011, axis, 0.004, 0.022, plastic);
    let tube_center = root + axis * (s.tube_length_m / 2.0 + 0.003);
    let tube = rod(
        "foam tube",
        tube_center,
        axis,
        s.tube_radius_m,
        s.tube_length_m,
        materials::RED_FOAM.scaled(rng.random_range(0.85..1.15)),
    );
    // The box the tube may reach on a turned toggle, whatever its tilt; a caretaker measures
    // the tube itself.
    let reach = s.tube_length_m / 2.0 + s.tube_radius_m;
    Device {
        primitives: vec![plate, lever, tube],
        tag_center: tube_center,
        tag_extent: extent_of(
            (tube_center - Vector3::repeat(reach)).into(),
            (tube_center + Vector3::repeat(reach)).into(),
        ),
        tag_size: [s.tube_length_m, 2.0 * s.tube_radius_m],
        extent: extent_of([0.0, -PLATE[1], z - PLATE[2]], [0.06, PLATE[1], z + PLATE[2]]),
        wall_x: 0.0,
        tops: vec![],
    }
}

pub(super) fn rocker(r: &Rocker, rng: &mut impl Rng) -> Device {
    let plastic = pick(&materials::PLASTICS, rng);
    let z = r.plate_height_m;
    let plate = slab(
        "rocker plate",
        [0.0, -PLATE[1], z - PLATE[2]],
        [PLATE[0], PLATE[1], z + PLATE[2]],
        plastic,
    );
    // The paddle rocks ±4° about the horizontal axis along the plate; the patch rocks with it.
    let rock = 4f64.to_radians() * if r.rocker_up { -1.0 } else { 1.0 };
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), rock);
    let paddle_depth = rng.random_range(0.006..0.011);
    let paddle_center = Point3::new(PLATE[0] + paddle_depth / 2.0, 0.0, z);
    let paddle = Primitive::new(
        "rocker paddle",
        Shape::Box { half_extents: [paddle_depth / 2.0, 0.017, 0.0335] },
        Isometry3::from_parts(Translation3::from(paddle_center.coords), rotation),
        plastic,
    );
    let patch_center = paddle_center
        + rotation * Vector3::new(paddle_depth / 2.0 + r.patch_thickness_m / 2.0, 0.0, 0.0);
    let patch = Primitive::new(
        "dycem patch",
        Shape::Box {
            half_extents: [
                r.patch_thickness_m / 2.0,
                r.patch_width_m / 2.0,
                r.patch_height_m / 2.0,
            ],
        },
        Isometry3::from_parts(Translation3::from(patch_center.coords), rotation),
        materials::RED_DYCEM.scaled(rng.random_range(0.85..1.15)),
    );
    let front = patch_center + rotation * Vector3::new(r.patch_thickness_m / 2.0, 0.0, 0.0);
    let (hw, hh) = (r.patch_width_m / 2.0, r.patch_height_m / 2.0);
    Device {
        primitives: vec![plate, paddle, patch],
        tag_center: front,
        tag_extent: extent_of([PLATE[0], -hw, z - hh], [front.x + 0.005, hw, z + hh]),
        tag_size: [2.0 * hw.max(hh), 2.0 * hw.min(hh)],
        extent: extent_of([0.0, -PLATE[1], z - PLATE[2]], [0.03, PLATE[1], z + PLATE[2]]),
        wall_x: 0.0,
        tops: vec![],
    }
}
