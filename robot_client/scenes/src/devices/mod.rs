//! The paper's five tagged devices, built from their drawn dimensions as primitives in the
//! device's own frame: x along the backing surface's normal (toward the room), z up, y along the
//! surface; the origin on the floor, on the backing surface, under the tag's centre.
//!
//! Each builder also says where its tag is (the centre of the tag's visible front; the axis
//! middle for a foam tube, whose visible surface lies within its radius of it), where the room's
//! wall stands behind it, and which horizontal tops a small object could stand on.
//!
//! Here are the devices' kinds, their parameters and what a built device tells the scene; each
//! device's builder has its own file beside this one, the switches sharing theirs.

use nalgebra::{Point3, Vector3};
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::scene::Primitive;

mod drawer;
mod lamp;
mod parts;
mod switches;
mod trash_can;

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

    /// Its two largest sides, the larger first, metres: the size a caretaker registers for a
    /// tag lying flat within it.
    pub fn two_largest_sides(&self) -> [f64; 2] {
        let mut sides: Vec<f64> = (self.max - self.min).iter().copied().collect();
        sides.sort_by(|a, b| b.total_cmp(a));
        [sides[0], sides[1]]
    }
}

/// A device built: its primitives and what the scene around it needs to know, device frame.
#[derive(Debug, Clone)]
pub struct Device {
    pub primitives: Vec<Primitive>,
    /// The tag's centre.
    pub tag_center: Point3<f64>,
    pub tag_extent: Extent,
    /// The tag's size as a caretaker measures it, the larger side first, metres: a patch's or
    /// a towel's sides, a foam tube's length and diameter.
    pub tag_size: [f64; 2],
    /// Where the device stands on the floor (and how high it reaches).
    pub extent: Extent,
    /// x of the room's wall behind the device (0 when the wall is the backing surface).
    pub wall_x: f64,
    pub tops: Vec<Top>,
}

/// Builds the device; `rng` draws the details no miss report needs (finishes, handle sizes).
pub fn build(parameters: &DeviceParameters, rng: &mut impl Rng) -> Device {
    match parameters {
        DeviceParameters::FlipSwitch(s) => switches::flip_switch(s, rng),
        DeviceParameters::Rocker(r) => switches::rocker(r, rng),
        DeviceParameters::Lamp(l) => lamp::lamp(l, rng),
        DeviceParameters::Drawer(d) => drawer::drawer(d, rng),
        DeviceParameters::TrashCan(c) => trash_can::trash_can(c, rng),
    }
}
