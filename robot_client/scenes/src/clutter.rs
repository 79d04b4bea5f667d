//! What a home has around a tagged device: the room itself (the wall behind, floor, ceiling), a
//! side wall, a neighbouring cabinet, door trim, a shelf or a side table, things on the floor,
//! and red things that are not the tag. All in the device frame of [`crate::devices`].

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::devices::Extent;
use crate::geometry::Shape;
use crate::materials::{self, Material};
use crate::scene::Primitive;

/// The room, a closed box: the wall behind the device at x = `wall_x_m`, the opposite wall
/// `depth_m` further into the room, end walls at y = `y_m`, floor and ceiling.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Room {
    pub wall_x_m: f64,
    pub depth_m: f64,
    pub y_m: [f64; 2],
    pub ceiling_m: f64,
    pub wall: Material,
    pub floor: Material,
}

impl Room {
    pub fn primitives(&self) -> Vec<Primitive> {
        let quarter = std::f64::consts::FRAC_PI_2;
        let (x0, x1) = (self.wall_x_m, self.wall_x_m + self.depth_m);
        let [y0, y1] = self.y_m;
        let (xc, yc, zc) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0, self.ceiling_m / 2.0);
        let (hx, hy, hz) = (self.depth_m / 2.0, (y1 - y0) / 2.0, self.ceiling_m / 2.0);
        // Rectangles lie in their x–y plane: turned about y they face along x, about x along y.
        let facing_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), quarter);
        let facing_y = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), quarter);
        let at = |x: f64, y: f64, z: f64, turn: UnitQuaternion<f64>| {
            Isometry3::from_parts(Translation3::new(x, y, z), turn)
        };
        let wall = |name: &str, half: [f64; 2], pose: Isometry3<f64>| {
            Primitive::new(name, Shape::Rectangle { half_size: half }, pose, self.wall)
        };
        vec![
            wall("wall", [hz, hy], at(x0, yc, zc, facing_x)),
            wall("opposite wall", [hz, hy], at(x1, yc, zc, facing_x)),
            wall("end wall", [hx, hz], at(xc, y0, zc, facing_y)),
            wall("end wall", [hx, hz], at(xc, y1, zc, facing_y)),
            Primitive::new(
                "floor",
                Shape::Rectangle { half_size: [hx, hy] },
                Isometry3::translation(xc, yc, 0.0),
                self.floor,
            ),
            Primitive::new(
                "ceiling",
                Shape::Rectangle { half_size: [hx, hy] },
                Isometry3::translation(xc, yc, self.ceiling_m),
                materials::WALLS[0],
            ),
        ]
    }
}

/// One piece of clutter, device frame, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "what", rename_all = "snake_case")]
pub enum Clutter {
    /// A wall at right angles to the main one, in the plane y = `y_m`, reaching `depth_m` into
    /// the room.
    SideWall { y_m: f64, depth_m: f64, material: Material },
    /// A cabinet beside the device, its front at x = `front_x_m`.
    NeighbourCabinet { y_m: [f64; 2], front_x_m: f64, height_m: f64, material: Material },
    /// A door's trim beside a switch: a narrow board standing `proud_m` off the wall.
    DoorTrim { y_m: f64, width_m: f64, proud_m: f64, material: Material },
    /// A wall shelf.
    Shelf { y_m: [f64; 2], depth_m: f64, top_m: f64, material: Material },
    /// A small table standing on the floor.
    SideTable { center_m: [f64; 2], half_size_m: [f64; 2], top_m: f64, material: Material },
    /// A box on the floor (a basket, a carton), turned by `yaw_rad`.
    FloorBox { center_m: [f64; 2], half_size_m: [f64; 3], yaw_rad: f64, material: Material },
    /// A round bin or plant pot on the floor.
    FloorBin { center_m: [f64; 2], radius_m: f64, height_m: f64, material: Material },
}

impl Clutter {
    pub fn name(&self) -> &'static str {
        match self {
            Self::SideWall { .. } => "side wall",
            Self::NeighbourCabinet { .. } => "neighbouring cabinet",
            Self::DoorTrim { .. } => "door trim",
            Self::Shelf { .. } => "shelf",
            Self::SideTable { .. } => "side table",
            Self::FloorBox { .. } => "floor box",
            Self::FloorBin { .. } => "floor bin",
        }
    }

    /// The primitives, given the x of the wall behind.
    pub fn primitives(&self, wall_x: f64) -> Vec<Primitive> {
        match *self {
            Self::SideWall { y_m, depth_m, material } => vec![Primitive::new(
                "side wall",
                Shape::Rectangle { half_size: [depth_m / 2.0, 1.3] },
                Isometry3::from_parts(
                    Translation3::new(wall_x + depth_m / 2.0, y_m, 1.3),
                    UnitQuaternion::from_axis_angle(
                        &Vector3::x_axis(),
                        std::f64::consts::FRAC_PI_2,
                    ),
                ),
                material,
            )],
            Self::NeighbourCabinet { y_m, front_x_m, height_m, material } => vec![block(
                "neighbouring cabinet",
                [wall_x, y_m[0], 0.0],
                [front_x_m, y_m[1], height_m],
                material,
            )],
            Self::DoorTrim { y_m, width_m, proud_m, material } => vec![block(
                "door trim",
                [wall_x, y_m - width_m / 2.0, 0.0],
                [wall_x + proud_m, y_m + width_m / 2.0, 2.05],
                material,
            )],
            Self::Shelf { y_m, depth_m, top_m, material } => vec![block(
                "shelf",
                [wall_x, y_m[0], top_m - 0.02],
                [wall_x + depth_m, y_m[1], top_m],
                material,
            )],
            Self::SideTable { center_m: [x, y], half_size_m: [hx, hy], top_m, material } => {
                let mut parts = vec![block(
                    "table top",
                    [x - hx, y - hy, top_m - 0.025],
                    [x + hx, y + hy, top_m],
                    material,
                )];
                for (sx, sy) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
                    let (lx, ly) = (x + sx * (hx - 0.03), y + sy * (hy - 0.03));
                    parts.push(block(
                        "table leg",
                        [lx - 0.02, ly - 0.02, 0.0],
                        [lx + 0.02, ly + 0.02, top_m - 0.025],
                        material,
                    ));
                }
                parts
            }
            Self::FloorBox { center_m: [x, y], half_size_m, yaw_rad, material } => {
                vec![Primitive::new(
                    "floor box",
                    Shape::Box { half_extents: half_size_m },
                    Isometry3::from_parts(
                        Translation3::new(x, y, half_size_m[2]),
                        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw_rad),
                    ),
                    material,
                )]
            }
            Self::FloorBin { center_m: [x, y], radius_m, height_m, material } => {
                vec![Primitive::new(
                    "floor bin",
                    Shape::Cylinder { radius: radius_m, half_length: height_m / 2.0, capped: true },
                    Isometry3::translation(x, y, height_m / 2.0),
                    material,
                )]
            }
        }
    }

    /// Where it stands, device frame, for keeping other things off it.
    pub fn extent(&self, wall_x: f64) -> Extent {
        let mut min = Vector3::repeat(f64::INFINITY);
        let mut max = Vector3::repeat(f64::NEG_INFINITY);
        for p in self.primitives(wall_x) {
            let (c, r) = p.shape.bounding_sphere();
            let c = p.pose.isometry() * c;
            min = min.inf(&(c.coords - Vector3::repeat(r)));
            max = max.sup(&(c.coords + Vector3::repeat(r)));
        }
        Extent { min: min.into(), max: max.into() }
    }
}

/// A red thing that is not the tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DistractorKind {
    Book,
    Mug,
    Cushion,
}

/// A red distractor where it lies, device frame, and its gap to the tag.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Distractor {
    pub kind: DistractorKind,
    /// Centre of its base on the surface it rests on, metres.
    pub base_m: [f64; 3],
    pub yaw_rad: f64,
    /// Nearest distance between it and the tag, metres.
    pub gap_m: f64,
}

impl Distractor {
    /// Its size along x, y and z before the yaw, metres.
    pub fn size(kind: DistractorKind) -> [f64; 3] {
        match kind {
            DistractorKind::Book => [0.16, 0.23, 0.03],
            DistractorKind::Mug => [0.082, 0.082, 0.095],
            DistractorKind::Cushion => [0.38, 0.38, 0.13],
        }
    }

    /// Its extent, for the gap to the tag (the yaw taken as the worst case).
    pub fn extent(kind: DistractorKind, base: [f64; 3]) -> Extent {
        let [sx, sy, sz] = Self::size(kind);
        let r = sx.hypot(sy) / 2.0;
        let [x, y, z] = base;
        Extent { min: [x - r, y - r, z].into(), max: [x + r, y + r, z + sz].into() }
    }

    pub fn primitives(&self) -> Vec<Primitive> {
        let [sx, sy, sz] = Self::size(self.kind);
        let [x, y, z] = self.base_m;
        let pose = Isometry3::from_parts(
            Translation3::new(x, y, z + sz / 2.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.yaw_rad),
        );
        match self.kind {
            DistractorKind::Book => vec![Primitive::new(
                "red book",
                Shape::Box { half_extents: [sx / 2.0, sy / 2.0, sz / 2.0] },
                pose,
                materials::RED_BOOK,
            )],
            DistractorKind::Mug => vec![
                Primitive::new(
                    "red mug",
                    Shape::Cylinder { radius: sx / 2.0, half_length: sz / 2.0, capped: true },
                    pose,
                    materials::RED_MUG,
                ),
                Primitive::new(
                    "red mug handle",
                    Shape::Box { half_extents: [0.012, 0.006, 0.03] },
                    pose * Isometry3::translation(sx / 2.0 + 0.01, 0.0, 0.0),
                    materials::RED_MUG,
                ),
            ],
            DistractorKind::Cushion => vec![Primitive::new(
                "red cushion",
                Shape::Box { half_extents: [sx / 2.0, sy / 2.0, sz / 2.0] },
                pose,
                materials::RED_CUSHION,
            )],
        }
    }
}

fn block(name: &str, a: [f64; 3], b: [f64; 3], material: Material) -> Primitive {
    let center = Vector3::new((a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0);
    let half = [(b[0] - a[0]).abs() / 2.0, (b[1] - a[1]).abs() / 2.0, (b[2] - a[2]).abs() / 2.0];
    Primitive::new(name, Shape::Box { half_extents: half }, Isometry3::from(center), material)
}
