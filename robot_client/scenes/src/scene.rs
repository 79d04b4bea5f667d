//! A scene as data: primitives (a shape, where it stands and what it is made of) and lights, all
//! in the robot's base frame (x forward, y left, z up, metres). Serialisable, so a scene can be
//! written out beside its renders and read back.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::geometry::Shape;
use crate::lighting::Lights;
use crate::materials::Material;

/// A rigid pose: maps the shape's own frame into the base frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Metres.
    pub translation: [f64; 3],
    /// Unit quaternion `[qx, qy, qz, qw]`.
    pub rotation_xyzw: [f64; 4],
}

impl Pose {
    pub fn from_isometry(iso: &Isometry3<f64>) -> Self {
        let q = iso.rotation.quaternion();
        let t = iso.translation.vector;
        Self { translation: [t.x, t.y, t.z], rotation_xyzw: [q.i, q.j, q.k, q.w] }
    }

    pub fn isometry(&self) -> Isometry3<f64> {
        let [x, y, z] = self.translation;
        let [qx, qy, qz, qw] = self.rotation_xyzw;
        Isometry3::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_quaternion(Quaternion::new(qw, qx, qy, qz)),
        )
    }

    /// A pose that only moves.
    pub fn at(translation: Vector3<f64>) -> Self {
        Self::from_isometry(&Isometry3::translation(translation.x, translation.y, translation.z))
    }
}

/// One solid or surface of the scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Primitive {
    /// What it is ("wall", "drawer front 2", "towel strip 1"), for reading a scene file.
    pub name: String,
    pub shape: Shape,
    pub pose: Pose,
    pub material: Material,
}

impl Primitive {
    pub fn new(
        name: impl Into<String>,
        shape: Shape,
        pose: Isometry3<f64>,
        material: Material,
    ) -> Self {
        Self { name: name.into(), shape, pose: Pose::from_isometry(&pose), material }
    }

    /// The same primitive moved by `by` (applied after its own pose).
    pub fn transformed(&self, by: &Isometry3<f64>) -> Self {
        Self { pose: Pose::from_isometry(&(by * self.pose.isometry())), ..self.clone() }
    }
}

/// Everything the sensors can see.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    pub primitives: Vec<Primitive>,
    pub lights: Lights,
}
