//! The CDR of every message the node speaks, byte for byte against what Cyclone DDS's Python
//! binding writes for the same message (`fixtures/*.cdr`, made by `peer/capture_fixtures.py`
//! with the values built here): a field out of place or a wrong alignment shows as a diff.

use pps_ros2::cdr::{decode, encode};
use pps_ros2::msg::builtin::{ColorRgba, Duration, Header, Time};
use pps_ros2::msg::geometry::{
    Point, PointStamped, Pose, PoseStamped, Quaternion, Transform, TransformStamped, Vector3,
};
use pps_ros2::msg::pps::{TagEntry, TagRead, TagReads, Trial};
use pps_ros2::msg::sensor::{
    CameraInfo, CompressedImage, Image, PointCloud2, PointField, RegionOfInterest,
};
use pps_ros2::msg::tf::TfMessage;
use pps_ros2::msg::visualization::{
    HumbleMarkerArray, Marker, MarkerArray, MeshFile, UvCoordinate,
};

const STAMP: Time = Time { sec: 1764583200, nanosec: 123456789 };

fn header(frame: &str) -> Header {
    Header { stamp: STAMP, frame_id: frame.into() }
}

fn fixture(name: &str) -> Vec<u8> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Our bytes are the peer's, and the peer's bytes read back as our message.
fn same_as_peer<M>(name: &str, message: M)
where
    M: serde::Serialize + serde::de::DeserializeOwned + PartialEq + std::fmt::Debug,
{
    let theirs = fixture(&format!("{name}.cdr"));
    let ours = encode(&message).unwrap();
    assert_eq!(ours, theirs, "{name}: our CDR differs from Cyclone DDS's");
    let read: M = decode(&theirs).unwrap();
    assert_eq!(read, message, "{name}: Cyclone DDS's CDR reads back differently");
}

fn quaternion(x: f64, y: f64, z: f64, w: f64) -> Quaternion {
    Quaternion { x, y, z, w }
}

#[test]
fn image() {
    same_as_peer(
        "image",
        Image {
            header: header("camera_optical"),
            height: 2,
            width: 3,
            encoding: "bgr8".into(),
            is_bigendian: 0,
            step: 10,
            data: (0..20).collect(),
        },
    );
}

#[test]
fn camera_info() {
    same_as_peer(
        "camera_info",
        CameraInfo {
            header: header("cam"),
            height: 960,
            width: 1280,
            distortion_model: "plumb_bob".into(),
            d: vec![0.1, -0.25, 0.001, 0.002, 0.0],
            k: [1000.5, 0.0, 640.25, 0.0, 1001.5, 480.75, 0.0, 0.0, 1.0],
            r: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            p: [1000.5, 0.0, 640.25, 0.0, 0.0, 1001.5, 480.75, 0.0, 0.0, 0.0, 1.0, 0.0],
            binning_x: 1,
            binning_y: 2,
            roi: RegionOfInterest {
                x_offset: 3,
                y_offset: 4,
                height: 5,
                width: 6,
                do_rectify: true,
            },
        },
    );
}

#[test]
fn point_cloud2() {
    let field =
        |name: &str, offset, datatype| PointField { name: name.into(), offset, datatype, count: 1 };
    same_as_peer(
        "point_cloud2",
        PointCloud2 {
            header: header("base_link"),
            height: 1,
            width: 2,
            fields: vec![
                field("z", 0, PointField::FLOAT32),
                field("x", 4, PointField::FLOAT32),
                field("y", 8, PointField::FLOAT32),
                field("intensity", 12, PointField::UINT8),
            ],
            is_bigendian: false,
            point_step: 13,
            row_step: 26,
            data: (100..126).collect(),
            is_dense: true,
        },
    );
}

#[test]
fn tf_message() {
    let stamped = |parent: &str, child: &str, t: [f64; 3], q: Quaternion| TransformStamped {
        header: header(parent),
        child_frame_id: child.into(),
        transform: Transform { translation: Vector3 { x: t[0], y: t[1], z: t[2] }, rotation: q },
    };
    same_as_peer(
        "tf_message",
        TfMessage {
            transforms: vec![
                stamped(
                    "base_link",
                    "head",
                    [0.1, -0.2, 1.3],
                    quaternion(0.0, 0.0, 0.38268343, 0.92387953),
                ),
                stamped(
                    "head",
                    "camera_optical",
                    [0.05, 0.0, 0.0],
                    quaternion(-0.5, 0.5, -0.5, 0.5),
                ),
            ],
        },
    );
}

#[test]
fn point_stamped() {
    same_as_peer(
        "point_stamped",
        PointStamped { header: header("base_link"), point: Point { x: 1.25, y: -0.5, z: 0.875 } },
    );
}

#[test]
fn pose_stamped() {
    same_as_peer(
        "pose_stamped",
        PoseStamped {
            header: header("map"),
            pose: Pose {
                position: Point { x: 2.0, y: 3.5, z: 0.0 },
                orientation: quaternion(0.0, 0.0, 0.6, 0.8),
            },
        },
    );
}

#[test]
fn marker_array() {
    let clear = Marker {
        header: header("base_link"),
        ns: "pps".into(),
        id: 0,
        kind: Marker::ARROW,
        action: Marker::DELETEALL,
        ..Marker::default()
    };
    let tag = Marker {
        header: header("base_link"),
        ns: "pps".into(),
        id: 4,
        kind: Marker::POINTS,
        action: Marker::ADD,
        pose: Pose {
            position: Point { x: 0.5, y: 0.25, z: 1.0 },
            orientation: Quaternion::default(),
        },
        scale: Vector3 { x: 0.008, y: 0.008, z: 0.008 },
        color: ColorRgba { r: 1.0, g: 0.125, b: 0.125, a: 1.0 },
        lifetime: Duration { sec: 2, nanosec: 500_000_000 },
        frame_locked: true,
        points: vec![Point { x: 1.0, y: 2.0, z: 3.0 }, Point { x: -1.0, y: 0.5, z: 0.25 }],
        colors: vec![ColorRgba { r: 0.0, g: 0.5, b: 1.0, a: 0.75 }],
        texture_resource: "embedded://tex".into(),
        texture: CompressedImage {
            header: header("t"),
            format: "png".into(),
            data: vec![137, 80, 78],
        },
        uv_coordinates: vec![UvCoordinate { u: 0.25, v: 0.75 }],
        text: "tag".into(),
        mesh_resource: "package://pps/mesh.dae".into(),
        mesh_file: MeshFile { filename: "m.stl".into(), data: vec![1, 2, 3, 4, 5] },
        mesh_use_embedded_materials: true,
    };
    same_as_peer("marker_array", MarkerArray { markers: vec![clear, tag.clone()] });
    // Humble's layout of the same marker: what the node publishes under ROS_DISTRO=humble.
    same_as_peer(
        "marker_array_humble",
        HumbleMarkerArray::from(MarkerArray { markers: vec![tag] }),
    );
}

#[test]
fn tag_reads() {
    same_as_peer(
        "tag_reads",
        TagReads {
            stamp: STAMP,
            reads: vec![
                TagRead { epc: "E20034120000000000001001".into(), rssi_dbm: -47.5, antenna: 1 },
                TagRead { epc: "355AB1C6".into(), rssi_dbm: -61.25, antenna: 3 },
            ],
        },
    );
}

#[test]
fn tag_entry() {
    same_as_peer(
        "tag_entry",
        TagEntry {
            stamp: STAMP,
            epc: "E20034120000000000001001".into(),
            ambiguous: true,
            revision: "r3".into(),
            entry_json: r#"{"epc":"E20034120000000000001001"}"#.into(),
            unavailable_actions: vec!["on".into(), "off".into()],
            error: String::new(),
        },
    );
}

#[test]
fn trial() {
    same_as_peer(
        "trial",
        Trial { trial_json: r#"{"id":"7d1f2b9e-4c3a-4e55-9a41-0c2d9b6e8f10"}"#.into() },
    );
}

#[test]
fn a_payload_that_is_not_little_endian_cdr_is_refused() {
    let mut big_endian = fixture("trial.cdr");
    big_endian[1] = 0x00;
    assert!(decode::<Trial>(&big_endian).unwrap_err().contains("not little-endian"));
    assert!(decode::<Trial>(&[0, 1]).is_err());
    let truncated = &fixture("image.cdr")[..40];
    assert!(decode::<Image>(truncated).is_err());
}
