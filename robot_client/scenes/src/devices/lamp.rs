//! The floor lamp, its pull chain carrying a foam tube.

use nalgebra::{Isometry3, Point3, Vector3};
use rand::Rng;

use super::parts::{extent_of, pick, rod};
use super::{Device, Lamp};
use crate::geometry::Shape;
use crate::materials;
use crate::scene::Primitive;

pub(super) fn lamp(l: &Lamp, rng: &mut impl Rng) -> Device {
    let metal = if rng.random_bool(0.5) { materials::CHROME } else { materials::BLACK_METAL };
    let tube_center = Point3::new(l.wall_gap_m, 0.0, l.tube_height_m);
    let pole_x = l.wall_gap_m + l.pole_offset_m[0];
    let pole_y = l.pole_offset_m[1];
    // Nothing of the lamp may enter the wall.
    let shade_radius = l.shade_radius_m.min(pole_x - 0.02);
    let shade_height = rng.random_range(0.18..0.28);
    let pole_top = l.shade_bottom_m + shade_height * 0.7;
    let base_radius = rng.random_range(0.12f64..0.16).min(pole_x - 0.01);
    let base = rod(
        "lamp base",
        Point3::new(pole_x, pole_y, 0.012),
        Vector3::z(),
        base_radius,
        0.024,
        metal,
    );
    let pole_radius = rng.random_range(0.010..0.015);
    let pole = rod(
        "lamp pole",
        Point3::new(pole_x, pole_y, pole_top / 2.0),
        Vector3::z(),
        pole_radius,
        pole_top,
        metal,
    );
    let shade = Primitive::new(
        "lamp shade",
        Shape::Frustum {
            bottom_radius: shade_radius,
            top_radius: shade_radius * rng.random_range(0.55..0.8),
            height: shade_height,
        },
        Isometry3::translation(pole_x, pole_y, l.shade_bottom_m),
        pick(&materials::SHADES, rng),
    );
    let socket_z = l.shade_bottom_m + 0.04;
    let tube_top = l.tube_height_m + l.tube_length_m / 2.0;
    let chain = rod(
        "pull chain",
        Point3::new(l.wall_gap_m, 0.0, (socket_z + tube_top) / 2.0),
        Vector3::z(),
        0.0015,
        socket_z - tube_top,
        metal,
    );
    let tube = rod(
        "foam tube",
        tube_center,
        Vector3::z(),
        l.tube_radius_m,
        l.tube_length_m,
        materials::RED_FOAM.scaled(rng.random_range(0.85..1.15)),
    );
    let (r, h) = (l.tube_radius_m, l.tube_length_m / 2.0);
    Device {
        primitives: vec![base, pole, shade, chain, tube],
        tag_center: tube_center,
        tag_extent: extent_of(
            [tube_center.x - r, -r, tube_center.z - h],
            [tube_center.x + r, r, tube_center.z + h],
        ),
        tag_size: [l.tube_length_m, 2.0 * r],
        extent: extent_of(
            [pole_x - shade_radius, pole_y - shade_radius, 0.0],
            [pole_x + shade_radius, pole_y + shade_radius, pole_top],
        ),
        wall_x: 0.0,
        tops: vec![],
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::super::*;

    #[test]
    fn the_lamp_keeps_out_of_the_wall() {
        let l = Lamp {
            tube_height_m: 1.1,
            tube_radius_m: 0.015,
            tube_length_m: 0.12,
            wall_gap_m: 0.15,
            pole_offset_m: [-0.05, 0.03],
            shade_bottom_m: 1.4,
            shade_radius_m: 0.25,
        };
        let device = build(&DeviceParameters::Lamp(l), &mut ChaCha8Rng::seed_from_u64(2));
        assert!(device.extent.min.x > 0.0, "{:?}", device.extent);
        assert_eq!(device.tag_center, Point3::new(0.15, 0.0, 1.1));
    }
}
