//! Furnishing a device's surroundings from a seed: a side wall, a neighbouring cabinet, door
//! trim, a shelf or side table, things on the floor and a red distractor near the tag, all kept
//! off the device and out of the line the sensors see the tag along.

use nalgebra::{Point3, Vector2};
use rand::Rng;

use crate::clutter::{Clutter, Distractor, DistractorKind};
use crate::devices::{self, Device, DeviceKind, DeviceParameters, Extent};
use crate::draw::Draw;
use crate::materials;

/// Distance in the floor plane from `p` to the segment `a`–`b`.
fn to_segment(p: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (a + ab * t - p).norm()
}

fn overlaps(a: &Extent, b: &Extent, margin: f64) -> bool {
    a.min.x < b.max.x + margin
        && b.min.x < a.max.x + margin
        && a.min.y < b.max.y + margin
        && b.min.y < a.max.y + margin
}

/// Clutter and a red distractor around the device, kept off it and out of the sensors' view of
/// the tag.
pub(crate) fn draw_clutter(
    parameters: &DeviceParameters,
    device: &Device,
    camera: &Point3<f64>,
    camera_side: f64,
    d: &mut Draw,
) -> (Vec<Clutter>, Option<Distractor>) {
    let wall = device.wall_x;
    let kind = parameters.kind();
    let mut clutter = Vec::new();
    let mut taken = vec![device.extent];
    let away = -camera_side;
    let furniture =
        |d: &mut Draw| materials::FURNITURE[d.rng.random_range(0..materials::FURNITURE.len())];
    if d.chance(0.35) {
        let edge = if away > 0.0 { device.extent.max.y } else { device.extent.min.y };
        let y_m = edge + away * d.u(0.3, 1.0);
        let material = materials::WALLS[d.rng.random_range(0..materials::WALLS.len())];
        clutter.push(Clutter::SideWall { y_m, depth_m: d.u(1.0, 2.5), material });
    }
    let boxed = matches!(kind, DeviceKind::Drawer | DeviceKind::TrashCan);
    if boxed && d.chance(0.4) {
        let edge = if away > 0.0 { device.extent.max.y } else { device.extent.min.y };
        let near = edge + away * d.u(0.0, 0.1);
        let far = near + away * d.u(0.4, 0.9);
        let c = Clutter::NeighbourCabinet {
            y_m: [near.min(far), near.max(far)],
            front_x_m: d.u(-0.15, 0.1),
            height_m: d.u(0.5, 1.1),
            material: furniture(d),
        };
        taken.push(c.extent(wall));
        clutter.push(c);
    }
    let switch = matches!(kind, DeviceKind::FlipSwitch | DeviceKind::Rocker);
    if switch && d.chance(0.4) {
        let side = if camera_side.abs() > 0.0 && d.chance(0.7) { away } else { d.sign() };
        let material = materials::WALLS[d.rng.random_range(0..materials::WALLS.len())];
        clutter.push(Clutter::DoorTrim {
            y_m: side * d.u(0.12, 0.3),
            width_m: d.u(0.05, 0.09),
            proud_m: d.u(0.01, 0.02),
            material,
        });
    }
    // Where a distractor could stand: the device's own tops, or a shelf or table put beside it.
    let mut tops = device.tops.clone();
    let wants_distractor = d.chance(0.45);
    if wants_distractor && switch {
        let inner = away * d.u(0.08, 0.18);
        let outer = inner + away * d.u(0.25, 0.45);
        let depth_m = d.u(0.15, 0.25);
        let top_m = device.tag_center.z - d.u(0.12, 0.3);
        clutter.push(Clutter::Shelf {
            y_m: [inner.min(outer), inner.max(outer)],
            depth_m,
            top_m,
            material: furniture(d),
        });
        tops.push(devices::Top {
            x: [wall + 0.01, wall + depth_m - 0.01],
            y: [inner.min(outer), inner.max(outer)],
            z: top_m,
        });
    }
    if wants_distractor && kind == DeviceKind::Lamp {
        let (hx, hy) = (d.u(0.18, 0.25), d.u(0.18, 0.25));
        let edge = if away > 0.0 { device.extent.max.y } else { device.extent.min.y };
        let center = [wall + hx + 0.02, edge + away * (hy + d.u(0.02, 0.12))];
        let top_m = d.u(0.6, 0.95);
        let table = Clutter::SideTable {
            center_m: center,
            half_size_m: [hx, hy],
            top_m,
            material: furniture(d),
        };
        taken.push(table.extent(wall));
        clutter.push(table);
        tops.push(devices::Top {
            x: [center[0] - hx + 0.02, center[0] + hx - 0.02],
            y: [center[1] - hy + 0.02, center[1] + hy - 0.02],
            z: top_m,
        });
    }
    // Things on the floor keep away from the device and from the line the sensors see the tag along.
    let eye = camera.xy().coords;
    let tag = device.tag_center.xy().coords;
    let distractor = if wants_distractor {
        place_distractor(device, &tops, &taken, (eye, tag), d)
    } else {
        None
    };
    if let Some(x) = &distractor
        && x.kind == DistractorKind::Cushion
    {
        taken.push(Distractor::extent(x.kind, x.base_m));
    }
    for _ in 0..d.rng.random_range(0..=2) {
        for _ in 0..30 {
            let center_m = [d.u(wall + 0.1, wall + 1.4), d.u(-1.3, 1.3)];
            let c = if d.chance(0.5) {
                Clutter::FloorBox {
                    center_m,
                    half_size_m: [d.u(0.12, 0.25), d.u(0.12, 0.25), d.u(0.1, 0.25)],
                    yaw_rad: d.u(0.0, std::f64::consts::PI),
                    material: materials::CLUTTER[d.rng.random_range(0..materials::CLUTTER.len())],
                }
            } else {
                Clutter::FloorBin {
                    center_m,
                    radius_m: d.u(0.1, 0.18),
                    height_m: d.u(0.2, 0.5),
                    material: materials::CLUTTER[d.rng.random_range(0..materials::CLUTTER.len())],
                }
            };
            let e = c.extent(wall);
            let radius = (e.max.x - e.min.x).max(e.max.y - e.min.y) / 2.0;
            let clear = to_segment(Vector2::from(center_m), eye, tag) > radius + 0.15
                && Vector2::from(center_m).metric_distance(&eye) > radius + 0.4;
            if clear && !taken.iter().any(|t| overlaps(t, &e, 0.05)) {
                taken.push(e);
                clutter.push(c);
                break;
            }
        }
    }
    (clutter, distractor)
}

/// A red book or mug on one of `tops`, or a cushion on the floor, 12 cm or more from the tag and
/// preferably within 30 cm of it.
fn place_distractor(
    device: &Device,
    tops: &[devices::Top],
    taken: &[Extent],
    (eye, tag): (Vector2<f64>, Vector2<f64>),
    d: &mut Draw,
) -> Option<Distractor> {
    let mut best: Option<Distractor> = None;
    for _ in 0..60 {
        let on_floor = tops.is_empty() || d.chance(0.2);
        let kind = if on_floor {
            DistractorKind::Cushion
        } else if d.chance(0.5) {
            DistractorKind::Book
        } else {
            DistractorKind::Mug
        };
        let [sx, sy, _] = Distractor::size(kind);
        let r = sx.hypot(sy) / 2.0;
        let base_m = if on_floor {
            [d.u(device.wall_x + r + 0.02, device.wall_x + 0.8), d.u(-0.9, 0.9), 0.0]
        } else {
            let top = tops[d.rng.random_range(0..tops.len())];
            if top.x[1] - top.x[0] < 2.0 * r * 0.8 || top.y[1] - top.y[0] < 2.0 * r {
                continue;
            }
            // Set back from a front edge by a little more than its own radius, so it hides nothing.
            [
                d.u(top.x[0] + r, (top.x[1] - r).max(top.x[0] + r)),
                d.u(top.y[0] + r, top.y[1] - r),
                top.z,
            ]
        };
        let extent = Distractor::extent(kind, base_m);
        let in_view = to_segment(Vector2::new(base_m[0], base_m[1]), eye, tag) < r + 0.15;
        if on_floor && (in_view || taken.iter().any(|t| overlaps(t, &extent, 0.03))) {
            continue;
        }
        let gap_m = extent.gap(&device.tag_extent);
        if gap_m < 0.12 {
            continue;
        }
        let candidate = Distractor { kind, base_m, yaw_rad: d.u(0.0, std::f64::consts::PI), gap_m };
        if gap_m <= 0.30 {
            return Some(candidate);
        }
        if best.is_none_or(|b| gap_m < b.gap_m) {
            best = Some(candidate);
        }
    }
    best
}
