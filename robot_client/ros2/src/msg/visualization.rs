//! `visualization_msgs`: the markers RViz draws.

use serde::{Deserialize, Serialize};

use super::builtin::{ColorRgba, Duration, Header};
use super::geometry::{Point, Pose, Vector3};
use super::ros_message;
use super::sensor::CompressedImage;

/// `visualization_msgs/UVCoordinate`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct UvCoordinate {
    pub u: f32,
    pub v: f32,
}

/// `visualization_msgs/MeshFile`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MeshFile {
    pub filename: String,
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
}

/// `visualization_msgs/Marker` (Iron and later: with texture and mesh file).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    pub header: Header,
    pub ns: String,
    pub id: i32,
    /// One of the shape constants, e.g. [`Marker::CUBE_LIST`].
    #[serde(rename = "type")]
    pub kind: i32,
    pub action: i32,
    pub pose: Pose,
    pub scale: Vector3,
    pub color: ColorRgba,
    pub lifetime: Duration,
    pub frame_locked: bool,
    pub points: Vec<Point>,
    pub colors: Vec<ColorRgba>,
    pub texture_resource: String,
    pub texture: CompressedImage,
    pub uv_coordinates: Vec<UvCoordinate>,
    pub text: String,
    pub mesh_resource: String,
    pub mesh_file: MeshFile,
    pub mesh_use_embedded_materials: bool,
}
ros_message!(Marker, "visualization_msgs", "Marker");

impl Marker {
    pub const ARROW: i32 = 0;
    pub const CUBE: i32 = 1;
    pub const SPHERE: i32 = 2;
    pub const CYLINDER: i32 = 3;
    pub const LINE_STRIP: i32 = 4;
    pub const LINE_LIST: i32 = 5;
    pub const CUBE_LIST: i32 = 6;
    pub const SPHERE_LIST: i32 = 7;
    pub const POINTS: i32 = 8;
    pub const TEXT_VIEW_FACING: i32 = 9;
    pub const TRIANGLE_LIST: i32 = 11;

    pub const ADD: i32 = 0;
    pub const DELETE: i32 = 2;
    pub const DELETEALL: i32 = 3;
}

/// `visualization_msgs/MarkerArray`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MarkerArray {
    pub markers: Vec<Marker>,
}
ros_message!(MarkerArray, "visualization_msgs", "MarkerArray");

/// `visualization_msgs/Marker` as ROS 2 Humble has it: without the texture, UV coordinates and
/// mesh file that Iron added. Same DDS type name, different layout: a Humble RViz reads only
/// this one.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct HumbleMarker {
    pub header: Header,
    pub ns: String,
    pub id: i32,
    #[serde(rename = "type")]
    pub kind: i32,
    pub action: i32,
    pub pose: Pose,
    pub scale: Vector3,
    pub color: ColorRgba,
    pub lifetime: Duration,
    pub frame_locked: bool,
    pub points: Vec<Point>,
    pub colors: Vec<ColorRgba>,
    pub text: String,
    pub mesh_resource: String,
    pub mesh_use_embedded_materials: bool,
}
ros_message!(HumbleMarker, "visualization_msgs", "Marker");

/// `visualization_msgs/MarkerArray` of Humble's markers.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct HumbleMarkerArray {
    pub markers: Vec<HumbleMarker>,
}
ros_message!(HumbleMarkerArray, "visualization_msgs", "MarkerArray");

impl From<Marker> for HumbleMarker {
    /// The marker without the fields Humble lacks (the node never fills them).
    fn from(m: Marker) -> Self {
        Self {
            header: m.header,
            ns: m.ns,
            id: m.id,
            kind: m.kind,
            action: m.action,
            pose: m.pose,
            scale: m.scale,
            color: m.color,
            lifetime: m.lifetime,
            frame_locked: m.frame_locked,
            points: m.points,
            colors: m.colors,
            text: m.text,
            mesh_resource: m.mesh_resource,
            mesh_use_embedded_materials: m.mesh_use_embedded_materials,
        }
    }
}

impl From<MarkerArray> for HumbleMarkerArray {
    fn from(array: MarkerArray) -> Self {
        Self { markers: array.markers.into_iter().map(HumbleMarker::from).collect() }
    }
}

/// Which layout of `visualization_msgs/Marker` the robot's ROS 2 speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MarkerLayout {
    /// Humble (and older): no texture or mesh-file fields.
    Humble,
    /// Iron, Jazzy, Kilted and Rolling.
    Iron,
}

impl MarkerLayout {
    /// The layout of a ROS 2 distribution by its `ROS_DISTRO` name; later distributions than
    /// those known are taken to keep Iron's.
    pub fn of_distro(distro: &str) -> Self {
        match distro.trim().to_ascii_lowercase().as_str() {
            "foxy" | "galactic" | "humble" => Self::Humble,
            _ => Self::Iron,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn humble_and_older_get_the_old_layout_later_ones_the_new() {
        assert_eq!(MarkerLayout::of_distro("humble"), MarkerLayout::Humble);
        assert_eq!(MarkerLayout::of_distro(" Humble\n"), MarkerLayout::Humble);
        assert_eq!(MarkerLayout::of_distro("jazzy"), MarkerLayout::Iron);
        assert_eq!(MarkerLayout::of_distro("rolling"), MarkerLayout::Iron);
    }
}
