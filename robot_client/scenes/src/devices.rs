//! The paper's five tagged devices, built from their drawn dimensions as primitives in the
//! device's own frame: x along the backing surface's normal (toward the room), z up, y along the
//! surface; the origin on the floor, on the backing surface, under the tag's centre.
//!
//! Each builder also says where its tag is (the centre of the tag's visible front; the axis
//! middle for a foam tube, whose visible surface lies within its radius of it), where the room's
//! wall stands behind it, and which horizontal tops a small object could stand on.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::geometry::Shape;
use crate::materials::{self, Material};
use crate::scene::Primitive;

/// The five kinds of tagged device.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DeviceKind {
    /// A flip light switch, a red foam tube on its toggle.
    FlipSwitch,
    /// An ADA rocker switch, a red Dycem patch on the rocker and its wall plate.
    Rocker,
    /// A floor lamp, a red foam tube on its pull chain.
    Lamp,
    /// A drawer cabinet against a wall, a red towel on one drawer front.
    Drawer,
    /// A box-shaped trash can, the tag on its front face.
    TrashCan,
}

impl DeviceKind {
    pub const ALL: [DeviceKind; 5] =
        [Self::FlipSwitch, Self::Rocker, Self::Lamp, Self::Drawer, Self::TrashCan];

    pub fn name(self) -> &'static str {
        match self {
            Self::FlipSwitch => "flip_switch",
            Self::Rocker => "rocker",
            Self::Lamp => "lamp",
            Self::Drawer => "drawer",
            Self::TrashCan => "trash_can",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl std::fmt::Display for DeviceKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A flip switch: plate centre height, and the foam tube over its toggle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlipSwitch {
    pub plate_height_m: f64,
    pub toggle_up: bool,
    pub tube_radius_m: f64,
    pub tube_length_m: f64,
}

/// An ADA rocker: plate centre height and the Dycem patch on it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rocker {
    pub plate_height_m: f64,
    pub rocker_up: bool,
    pub patch_width_m: f64,
    pub patch_height_m: f64,
    pub patch_thickness_m: f64,
}

/// A floor lamp whose foam tube hangs on the pull chain `wall_gap_m` before the wall.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Lamp {
    pub tube_height_m: f64,
    pub tube_radius_m: f64,
    pub tube_length_m: f64,
    pub wall_gap_m: f64,
    /// The pole's offset from the chain, metres, along x (from the wall) and y.
    pub pole_offset_m: [f64; 2],
    pub shade_bottom_m: f64,
    pub shade_radius_m: f64,
}

/// A drawer cabinet against the wall with a towel over one drawer's handle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Drawer {
    pub front_width_m: f64,
    pub cabinet_height_m: f64,
    pub cabinet_depth_m: f64,
    pub drawers: u32,
    /// Which drawer carries the towel, 0 the top one.
    pub tag_drawer: u32,
    pub towel_width_m: f64,
    pub towel_height_m: f64,
    /// Gap between the towel's back and the drawer front, metres.
    pub towel_proud_m: f64,
    pub towel_thickness_m: f64,
    /// The towel's centre from the front's centre, along the front, metres.
    pub towel_offset_m: f64,
    pub wall_gap_m: f64,
}

/// A box-shaped trash can with the tag on its front face.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrashCan {
    pub width_m: f64,
    pub depth_m: f64,
    pub height_m: f64,
    pub patch_width_m: f64,
    pub patch_height_m: f64,
    pub patch_thickness_m: f64,
    /// Height of the patch's centre as a fraction of the can's.
    pub patch_level: f64,
    pub patch_offset_m: f64,
    pub wall_gap_m: f64,
}

/// A device's drawn dimensions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum DeviceParameters {
    FlipSwitch(FlipSwitch),
    Rocker(Rocker),
    Lamp(Lamp),
    Drawer(Drawer),
    TrashCan(TrashCan),
}

impl DeviceParameters {
    pub fn kind(&self) -> DeviceKind {
        match self {
            Self::FlipSwitch(_) => DeviceKind::FlipSwitch,
            Self::Rocker(_) => DeviceKind::Rocker,
            Self::Lamp(_) => DeviceKind::Lamp,
            Self::Drawer(_) => DeviceKind::Drawer,
            Self::TrashCan(_) => DeviceKind::TrashCan,
        }
    }

    /// The dimensions in a line, for printing a miss.
    pub fn summary(&self) -> String {
        let cm = |m: f64| m * 100.0;
        match self {
            Self::FlipSwitch(s) => format!(
                "plate at {:.2} m, tube r {:.1} × {:.1} cm, toggle {}",
                s.plate_height_m,
                cm(s.tube_radius_m),
                cm(s.tube_length_m),
                if s.toggle_up { "up" } else { "down" }
            ),
            Self::Rocker(r) => format!(
                "plate at {:.2} m, patch {:.1} × {:.1} cm",
                r.plate_height_m,
                cm(r.patch_width_m),
                cm(r.patch_height_m)
            ),
            Self::Lamp(l) => format!(
                "tube at {:.2} m, {:.0} cm before the wall, r {:.1} × {:.0} cm",
                l.tube_height_m,
                cm(l.wall_gap_m),
                cm(l.tube_radius_m),
                cm(l.tube_length_m)
            ),
            Self::Drawer(d) => format!(
                "front {:.2} m wide, {} drawers (towel on {}), towel {:.0} × {:.0} cm {:.1} cm proud",
                d.front_width_m,
                d.drawers,
                d.tag_drawer,
                cm(d.towel_width_m),
                cm(d.towel_height_m),
                cm(d.towel_proud_m)
            ),
            Self::TrashCan(c) => format!(
                "can {:.2} × {:.2} × {:.2} m, patch {:.0} × {:.0} cm",
                c.width_m,
                c.depth_m,
                c.height_m,
                cm(c.patch_width_m),
                cm(c.patch_height_m)
            ),
        }
    }
}

/// A horizontal top something can stand on, device frame, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Top {
    pub x: [f64; 2],
    pub y: [f64; 2],
    pub z: f64,
}

/// An axis-aligned box in the device frame: the tag's extent, a device's footprint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    pub min: Point3<f64>,
    pub max: Point3<f64>,
}

impl Extent {
    /// Gap between two boxes, metres (0 when they touch or overlap).
    pub fn gap(&self, other: &Extent) -> f64 {
        let d = |lo: f64, hi: f64, olo: f64, ohi: f64| (olo - hi).max(lo - ohi).max(0.0);
        Vector3::new(
            d(self.min.x, self.max.x, other.min.x, other.max.x),
            d(self.min.y, self.max.y, other.min.y, other.max.y),
            d(self.min.z, self.max.z, other.min.z, other.max.z),
        )
        .norm()
    }
}

/// A device built: its primitives and what the scene around it needs to know, device frame.
#[derive(Debug, Clone)]
pub struct Device {
    pub primitives: Vec<Primitive>,
    /// The tag's centre.
    pub tag_center: Point3<f64>,
    pub tag_extent: Extent,
    /// Where the device stands on the floor (and how high it reaches).
    pub extent: Extent,
    /// x of the room's wall behind the device (0 when the wall is the backing surface).
    pub wall_x: f64,
    pub tops: Vec<Top>,
}

/// Builds the device; `rng` draws the details no miss report needs (finishes, handle sizes).
pub fn build(parameters: &DeviceParameters, rng: &mut impl Rng) -> Device {
    match parameters {
        DeviceParameters::FlipSwitch(s) => flip_switch(s, rng),
        DeviceParameters::Rocker(r) => rocker(r, rng),
        DeviceParameters::Lamp(l) => lamp(l, rng),
        DeviceParameters::Drawer(d) => drawer(d, rng),
        DeviceParameters::TrashCan(c) => trash_can(c, rng),
    }
}

fn pick<T: Copy>(palette: &[T], rng: &mut impl Rng) -> T {
    palette[rng.random_range(0..palette.len())]
}

/// An axis-aligned box between two corners.
fn slab(name: &str, a: [f64; 3], b: [f64; 3], material: Material) -> Primitive {
    let center = Vector3::new((a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0);
    let half = [(b[0] - a[0]).abs() / 2.0, (b[1] - a[1]).abs() / 2.0, (b[2] - a[2]).abs() / 2.0];
    Primitive::new(name, Shape::Box { half_extents: half }, Isometry3::from(center), material)
}

/// A cylinder with its axis along `axis` through `center`.
fn rod(
    name: &str,
    center: Point3<f64>,
    axis: Vector3<f64>,
    radius: f64,
    length: f64,
    material: Material,
) -> Primitive {
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    Primitive::new(
        name,
        Shape::Cylinder { radius, half_length: length / 2.0, capped: true },
        Isometry3::from_parts(Translation3::from(center.coords), rotation),
        material,
    )
}

fn extent_of(a: [f64; 3], b: [f64; 3]) -> Extent {
    Extent {
        min: Point3::new(a[0].min(b[0]), a[1].min(b[1]), a[2].min(b[2])),
        max: Point3::new(a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])),
    }
}

/// Switch plates are 7 × 11.4 cm and 6 mm thick.
const PLATE: [f64; 3] = [0.006, 0.035, 0.057];

fn flip_switch(s: &FlipSwitch, rng: &mut impl Rng) -> Device {
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
    let reach = s.tube_length_m / 2.0 + s.tube_radius_m;
    Device {
        primitives: vec![plate, lever, tube],
        tag_center: tube_center,
        tag_extent: extent_of(
            (tube_center - Vector3::repeat(reach)).into(),
            (tube_center + Vector3::repeat(reach)).into(),
        ),
        extent: extent_of([0.0, -PLATE[1], z - PLATE[2]], [0.06, PLATE[1], z + PLATE[2]]),
        wall_x: 0.0,
        tops: vec![],
    }
}

fn rocker(r: &Rocker, rng: &mut impl Rng) -> Device {
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
        extent: extent_of([0.0, -PLATE[1], z - PLATE[2]], [0.03, PLATE[1], z + PLATE[2]]),
        wall_x: 0.0,
        tops: vec![],
    }
}

fn lamp(l: &Lamp, rng: &mut impl Rng) -> Device {
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
        extent: extent_of(
            [pole_x - shade_radius, pole_y - shade_radius, 0.0],
            [pole_x + shade_radius, pole_y + shade_radius, pole_top],
        ),
        wall_x: 0.0,
        tops: vec![],
    }
}

/// Drawer fronts are 18 mm boards with 3 mm gaps, standing on a plinth set back 5 cm.
const FRONT_THICKNESS: f64 = 0.018;
const FRONT_GAP: f64 = 0.003;

fn drawer(d: &Drawer, rng: &mut impl Rng) -> Device {
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
        extent: extent_of([back, y0 - overhang, 0.0], [handle_out + 0.01, y1 + overhang, h + 0.02]),
        wall_x: back - d.wall_gap_m,
        tops: vec![Top { x: [back + 0.02, -0.03], y: [y0 + 0.02, y1 - 0.02], z: h + 0.02 }],
    }
}

fn trash_can(c: &TrashCan, rng: &mut impl Rng) -> Device {
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

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
