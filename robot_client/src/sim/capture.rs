//! Recorded scenes: the robot placed 1.5 m from a device as in the paper's trials, and what its
//! camera, laser and operator give it there. Tests, the `scene` subcommand and the benchmark use
//! these to run perception on data exactly as a real robot would record it.

use std::path::Path;

use nalgebra::{Isometry2, Point3, Rotation2, Vector2};
use serde_json::json;

use super::body::{BodyGeometry, head_camera};
use super::laser::LaserModel;
use super::operator::{OperatorScript, SimOperator};
use super::robot::SimRobot;
use super::room::{Device, DeviceKind, Room};
use crate::hal::{
    CameraCalibration, ColorCamera, ColorImage, Operator, PlanarPose, PointCloud, TiltSweep,
    TiltingLaser,
};
use crate::sensor_files::{PlyFormat, SensorFileError, write_camera_file, write_ply, write_png};

/// Where the robot starts, around the tag at a fixed distance, facing it. Left and right are as
/// seen by a person standing in front of the device. The paper's four starts are evenly spaced
/// on a half-circle facing the tag: 22.5° and 67.5° either side of its normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartDirection {
    FarLeft,
    Left,
    Front,
    Right,
    FarRight,
}

impl StartDirection {
    /// The paper's four starts.
    pub const PAPER: [Self; 4] = [Self::FarLeft, Self::Left, Self::Right, Self::FarRight];

    /// Angle of the start from the tag's normal, radians, counter-clockwise seen from above.
    pub fn angle(self) -> f64 {
        let degrees: f64 = match self {
            Self::FarLeft => -67.5,
            Self::Left => -22.5,
            Self::Front => 0.0,
            Self::Right => 22.5,
            Self::FarRight => 67.5,
        };
        degrees.to_radians()
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::FarLeft => "far-left",
            Self::Left => "left",
            Self::Front => "front",
            Self::Right => "right",
            Self::FarRight => "far-right",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        [Self::FarLeft, Self::Left, Self::Front, Self::Right, Self::FarRight]
            .into_iter()
            .find(|d| d.name() == name)
    }
}

/// The robot's pose `distance` metres from `device`'s tag in `direction`, facing the tag.
pub fn start_pose(device: &Device, direction: StartDirection, distance: f64) -> PlanarPose {
    start_pose_at_angle(device, direction.angle(), distance)
}

/// The robot's pose `distance` metres from `device`'s tag, `angle` radians off the tag's
/// normal (counter-clockwise seen from above), facing the tag.
pub fn start_pose_at_angle(device: &Device, angle: f64, distance: f64) -> PlanarPose {
    let tag = Vector2::new(device.tag_center.x, device.tag_center.y);
    let normal = Vector2::new(device.tag_normal.x, device.tag_normal.y).normalize();
    let position = tag + Rotation2::new(angle) * normal * distance;
    let toward = tag - position;
    Isometry2::new(position, toward.y.atan2(toward.x))
}

/// How a scene is recorded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureSettings {
    pub camera: CameraCalibration,
    pub laser: LaserModel,
    pub sweep: TiltSweep,
    pub operator: OperatorScript,
}

impl CaptureSettings {
    /// Small and quick: 320×240, the laser cropped to ±40°, 0.25° tilt steps (~70 000 beams).
    pub fn small() -> Self {
        Self {
            camera: head_camera(0.25),
            laser: LaserModel { half_field_of_view: 40f64.to_radians(), ..LaserModel::default() },
            sweep: TiltSweep {
                from: -20f64.to_radians(),
                to: 35f64.to_radians(),
                step: 0.25f64.to_radians(),
            },
            operator: OperatorScript::default(),
        }
    }

    /// The benchmark's size: 1280×960 and ~200 000 laser points (±60°, 0.13° tilt steps).
    pub fn full() -> Self {
        Self {
            camera: head_camera(1.0),
            laser: LaserModel { half_field_of_view: 60f64.to_radians(), ..LaserModel::default() },
            sweep: TiltSweep {
                from: -20f64.to_radians(),
                to: 35f64.to_radians(),
                step: 0.13f64.to_radians(),
            },
            operator: OperatorScript::default(),
        }
    }
}

/// One recorded scene and its ground truth, base frame.
#[derive(Debug, Clone)]
pub struct SceneCapture {
    pub device: DeviceKind,
    pub image: ColorImage,
    pub cloud: PointCloud,
    pub calibration: CameraCalibration,
    /// Where the operator's laser-pointer estimate put the target.
    pub target: Point3<f64>,
    /// Where the device's tag truly is, and every tag of the room.
    pub tag_truth: Point3<f64>,
    pub all_tags: Vec<(DeviceKind, Point3<f64>)>,
    /// Outward normal of the device's tag, base frame.
    pub tag_normal: nalgebra::Vector3<f64>,
    pub world_from_base: PlanarPose,
}

/// Places the robot in `room` by `device` and records what it senses there.
pub fn capture_scene(
    room: Room,
    device: DeviceKind,
    direction: StartDirection,
    distance: f64,
    seed: u64,
    settings: &CaptureSettings,
) -> SceneCapture {
    let pose = start_pose(room.device(device), direction, distance);
    let geometry =
        BodyGeometry { camera: settings.camera, laser: settings.laser, ..BodyGeometry::default() };
    let robot = SimRobot::with_geometry(room, pose, geometry, seed);
    let operator = SimOperator::new(
        robot.clone(),
        OperatorScript { target: Some(device), ..settings.operator },
        seed ^ 0x5EED,
    );
    let image = robot.capture(true).expect("the simulated camera always captures");
    let cloud = robot.scan(&settings.sweep).expect("the capture settings hold a valid sweep");
    let target = operator
        .pointed_target()
        .expect("the simulated operator always answers")
        .expect("the operator points at the device");
    let state = robot.state();
    let base_from_world = state.body.world_from_base_3d().inverse();
    let device_info = state.room.device(device);
    SceneCapture {
        device,
        image,
        cloud,
        calibration: settings.camera,
        target,
        tag_truth: base_from_world * device_info.tag_center,
        all_tags: state
            .room
            .devices
            .iter()
            .map(|d| (d.kind, base_from_world * d.tag_center))
            .collect(),
        tag_normal: base_from_world * device_info.tag_normal,
        world_from_base: pose,
    }
}

impl SceneCapture {
    /// Writes `image.png`, `cloud.ply` (binary little-endian), `camera.json` and `scene.json`
    /// (the target and the truth) into `dir`, creating it.
    pub fn write(&self, dir: &Path) -> Result<(), SensorFileError> {
        std::fs::create_dir_all(dir).map_err(|e| crate::sensor_files::io_error(dir, e))?;
        write_png(&dir.join("image.png"), &self.image)?;
        write_ply(&dir.join("cloud.ply"), &self.cloud, PlyFormat::BinaryLittleEndian)?;
        write_camera_file(&dir.join("camera.json"), &self.calibration)?;
        let t = &self.target;
        let truth = &self.tag_truth;
        let scene = json!({
            "device": self.device.type_name(),
            "epc": self.device.epc().as_hex(),
            "frame": "robot base: x forward, y left, z up, metres",
            "target": [t.x, t.y, t.z],
            "tag_truth": [truth.x, truth.y, truth.z],
            "points": self.cloud.len(),
            "image": [self.image.width, self.image.height],
        });
        let path = dir.join("scene.json");
        std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap_or_default() + "\n")
            .map_err(|e| crate::sensor_files::io_error(&path, e))
    }

    /// The target as `--target` takes it.
    pub fn target_arg(&self) -> String {
        format!("{:.4},{:.4},{:.4}", self.target.x, self.target.y, self.target.z)
    }
}
