//! `geometry_msgs`: points, orientations, poses and transforms, metres and unit quaternions.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::builtin::Header;
use super::ros_message;

/// `geometry_msgs/Point`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// `geometry_msgs/Vector3`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// `geometry_msgs/Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

impl Default for Quaternion {
    /// The identity, as ROS 2 initialises it.
    fn default() -> Self {
        Self { x: 0.0, y: 0.0, z: 0.0, w: 1.0 }
    }
}

/// `geometry_msgs/Pose`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    pub position: Point,
    pub orientation: Quaternion,
}

/// `geometry_msgs/PoseStamped`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseStamped {
    pub header: Header,
    pub pose: Pose,
}
ros_message!(PoseStamped, "geometry_msgs", "PoseStamped");

/// `geometry_msgs/PointStamped`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PointStamped {
    pub header: Header,
    pub point: Point,
}
ros_message!(PointStamped, "geometry_msgs", "PointStamped");

/// `geometry_msgs/Transform`: where the child frame sits in the parent frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    pub translation: Vector3,
    pub rotation: Quaternion,
}

/// `geometry_msgs/TransformStamped`: `header.frame_id` is the parent, `child_frame_id` the child.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    pub header: Header,
    pub child_frame_id: String,
    pub transform: Transform,
}

impl From<Point3<f64>> for Point {
    fn from(p: Point3<f64>) -> Self {
        Self { x: p.x, y: p.y, z: p.z }
    }
}

impl From<Point> for Point3<f64> {
    fn from(p: Point) -> Self {
        Point3::new(p.x, p.y, p.z)
    }
}

impl From<UnitQuaternion<f64>> for Quaternion {
    fn from(q: UnitQuaternion<f64>) -> Self {
        Self { x: q.i, y: q.j, z: q.k, w: q.w }
    }
}

impl Pose {
    pub fn new(position: Point3<f64>, orientation: UnitQuaternion<f64>) -> Self {
        Self { position: position.into(), orientation: orientation.into() }
    }
}

impl Transform {
    /// The transform as an isometry mapping child-frame points into the parent frame, or
    /// `None` when its rotation is not a finite, non-zero quaternion.
    pub fn to_isometry(&self) -> Option<Isometry3<f64>> {
        let t = self.translation;
        let r = self.rotation;
        let q = nalgebra::Quaternion::new(r.w, r.x, r.y, r.z);
        let finite = [t.x, t.y, t.z, r.x, r.y, r.z, r.w].iter().all(|v| v.is_finite());
        if !finite || q.norm() < 1e-9 {
            return None;
        }
        Some(Isometry3::from_parts(
            Translation3::new(t.x, t.y, t.z),
            UnitQuaternion::from_quaternion(q),
        ))
    }

    pub fn from_isometry(iso: &Isometry3<f64>) -> Self {
        let t = iso.translation.vector;
        Self { translation: Vector3 { x: t.x, y: t.y, z: t.z }, rotation: iso.rotation.into() }
    }
}
