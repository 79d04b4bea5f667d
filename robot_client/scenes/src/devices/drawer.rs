//! The drawer cabinet against a wall, a towel hanging on one drawer front.

use nalgebra::{Point3, Vector3};
use rand::Rng;

use super::parts::{extent_of, pick, rod, slab};
use super::{Device, Drawer, Top};
use crate::materials;

/// Drawer fronts are 18 mm boards with 3 mm gaps, standing on a plinth set back 5 cm.
const FRONT_THICKNESS: f64 = 0.018;
const FRONT_GAP: f64 = 0.003;

pub(super) fn drawer(d: &Drawer, rng: &mut impl Rng) -> Device {
    let finish = pick(&materials::FURNITURE, rng);
    let metal = if rng.random_bool(0.5) { materials::CHROME } else { materials::BLACK_METAL };
    let towel = materials::RED_TOWEL.scaled(rng.random_range(0.85..1.15));
    let (w, h, depth) = (d.front_width_m, d.cabinet_height_m, d.cabinet_depth_m);
    // The front's centre sits `towel_offset_m` from the towel, which is at y = 0.
    let (y0, y1) = (-d.towel_offset_m - w / 2.0, -d.towel_offset_m + w / 2.0);
    let plinth = rng.random_range(0.05..0.10);
    let back = -depth;
    let overhang = rng.random_range(0.0..0.02);
    let mut primitives = vec![
        slab("cabinet body", [back, y0, plinth], [-FRONT_THICKNESS, y1, h], finish),
        slab("plinth", [back, y0 + 0.01, 0.0], [-0.05, y1 - 0.01, plinth], finish),
        slab("cabinet top", [back, y0 - overhang, h], [overhang, y1 + overhang, h + 0.02], finish),
    ];
    let drawer_height = (h - plinth) / f64::from(d.drawers);
    let handle_radius = rng.random_range(0.005..0.008);
    let handle_half = rng.random_range(0.05f64..0.09).min(w / 2.0 - 0.03);
    // Handles stand out enough to hang the towel on; with the towel flat, a usual 2.5–3.5 cm.
    let handle_out = if d.towel_proud_m >= 0.012 {
        d.towel_proud_m - handle_radius
    } else {
        rng.random_range(0.025..0.035)
    };
    let mut tag_center = Point3::origin();
    let mut tag_extent = extent_of([0.0; 3], [0.0; 3]);
    for k in 0..d.drawers {
        let top = h - f64::from(k) * drawer_height - FRONT_GAP / 2.0;
        let bottom = top - drawer_height + FRONT_GAP;
        primitives.push(slab(
            &format!("drawer front {k}"),
            [-FRONT_THICKNESS, y0 + 0.002, bottom],
            [0.0, y1 - 0.002, top],
            finish,
        ));
        let handle_z = top - drawer_height.min(0.2) * 0.25;
        let is_tag_drawer = k == d.tag_drawer;
        // A towel lying flat is tucked into the drawer's top gap, and that drawer has no handle.
        if !(is_tag_drawer && d.towel_proud_m < 0.012) {
            let bar = Point3::new(handle_out, 0.0, handle_z);
            primitives.push(rod(
                &format!("handle {k}"),
                bar,
                Vector3::y(),
                handle_radius,
                2.0 * handle_half,
                metal,
            ));
            for side in [-1.0, 1.0] {
                let post = Point3::new(handle_out / 2.0, side * (handle_half - 0.01), handle_z);
                primitives.push(rod(
                    &format!("handle post {k}"),
                    post,
                    Vector3::x(),
                    0.004,
                    handle_out,
                    metal,
                ));
            }
        }
        if is_tag_drawer {
            let t = d.towel_thickness_m;
            let towel_top = if d.towel_proud_m >= 0.012 { handle_z + handle_radius } else { top };
            let towel_bottom = (towel_top - d.towel_height_m).max(0.03);
            let strips = rng.random_range(3..=5);
            let strip_width = d.towel_width_m / f64::from(strips);
            let mut front_sum = 0.0;
            for s in 0..strips {
                // Folds: each strip hangs a few millimetres nearer or further.
                let fold = rng.random_range(-0.003..0.003f64).max(-d.towel_proud_m);
                let x_back = d.towel_proud_m + fold;
                front_sum += x_back + t;
                let ya = -d.towel_width_m / 2.0 + f64::from(s) * strip_width;
                primitives.push(slab(
                    &format!("towel strip {s}"),
                    [x_back, ya, towel_bottom],
                    [x_back + t, ya + strip_width, towel_top],
                    towel,
                ));
            }
            if d.towel_proud_m >= 0.012 {
                // Over the bar and down behind it.
                primitives.push(slab(
                    "towel fold",
                    [handle_out - handle_radius - t, -d.towel_width_m / 2.0, towel_top - 0.002],
                    [d.towel_proud_m + t, d.towel_width_m / 2.0, towel_top + t],
                    towel,
                ));
            }
            let front_x = front_sum / f64::from(strips);
            tag_center = Point3::new(front_x, 0.0, (towel_top + towel_bottom) / 2.0);
            tag_extent = extent_of(
                [0.0, -d.towel_width_m / 2.0, towel_bottom],
                [front_x + 0.005, d.towel_width_m / 2.0, towel_top + t],
            );
        }
    }
    Device {
        primitives,
        tag_center,
        tag_extent,
        tag_size: tag_extent.two_largest_sides(),
        extent: extent_of([back, y0 - overhang, 0.0], [handle_out + 0.01, y1 + overhang, h + 0.02]),
        wall_x: back - d.wall_gap_m,
        tops: vec![Top { x: [back + 0.02, -0.03], y: [y0 + 0.02, y1 - 0.02], z: h + 0.02 }],
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::super::*;

    #[test]
    fn the_towel_hangs_on_its_drawer_in_front_of_the_front() {
        let d = Drawer {
            front_width_m: 0.6,
            cabinet_height_m: 0.8,
            cabinet_depth_m: 0.5,
            drawers: 3,
            tag_drawer: 0,
            towel_width_m: 0.25,
            towel_height_m: 0.2,
            towel_proud_m: 0.02,
            towel_thickness_m: 0.008,
            towel_offset_m: 0.1,
            wall_gap_m: 0.01,
        };
        let device = build(&DeviceParameters::Drawer(d), &mut ChaCha8Rng::seed_from_u64(1));
        let c = device.tag_center;
        assert!(c.x > 0.02 && c.x < 0.035, "front of the towel {c}");
        assert!(c.z < 0.8 && c.z > 0.5, "on the top drawer {c}");
        assert!((device.wall_x + 0.51).abs() < 1e-12);
        let towel: Vec<_> = device.primitives.iter().filter(|p| p.material.is_tag).collect();
        assert!(towel.len() >= 4, "strips and the fold");
    }
}
