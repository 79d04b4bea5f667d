//! The box-shaped trash can, its tag on the front face.

use nalgebra::Point3;
use rand::Rng;

use super::parts::{extent_of, pick, slab};
use super::{Device, Top, TrashCan};
use crate::materials;

pub(super) fn trash_can(c: &TrashCan, rng: &mut impl Rng) -> Device {
    let finish = pick(&materials::CANS, rng);
    let (y0, y1) = (-c.patch_offset_m - c.width_m / 2.0, -c.patch_offset_m + c.width_m / 2.0);
    let back = -c.depth_m;
    let lid_height = rng.random_range(0.02..0.04);
    let mut primitives = vec![
        slab("can body", [back, y0, 0.0], [0.0, y1, c.height_m], finish),
        slab(
            "can lid",
            [back - 0.008, y0 - 0.008, c.height_m],
            [0.008, y1 + 0.008, c.height_m + lid_height],
            finish,
        ),
    ];
    if rng.random_bool(0.5) {
        let pedal_y = (y0 + y1) / 2.0;
        primitives.push(slab(
            "pedal",
            [0.0, pedal_y - 0.05, 0.01],
            [0.05, pedal_y + 0.05, 0.03],
            materials::BLACK_METAL,
        ));
    }
    let z = c.patch_level * c.height_m;
    let (hw, hh, t) = (c.patch_width_m / 2.0, c.patch_height_m / 2.0, c.patch_thickness_m);
    primitives.push(slab(
        "tag patch",
        [0.0, -hw, z - hh],
        [t, hw, z + hh],
        materials::RED_DYCEM.scaled(rng.random_range(0.85..1.15)),
    ));
    Device {
        primitives,
        tag_center: Point3::new(t, 0.0, z),
        tag_extent: extent_of([0.0, -hw, z - hh], [t, hw, z + hh]),
        tag_size: [2.0 * hw.max(hh), 2.0 * hw.min(hh)],
        extent: extent_of(
            [back - 0.008, y0 - 0.008, 0.0],
            [0.05, y1 + 0.008, c.height_m + lid_height],
        ),
        wall_x: back - c.wall_gap_m,
        tops: vec![Top {
            x: [back + 0.02, -0.02],
            y: [y0 + 0.02, y1 - 0.02],
            z: c.height_m + lid_height,
        }],
    }
}
