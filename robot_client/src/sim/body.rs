//! The simulated robot's body: where its base truly is, what its odometry believes, and where its
//! sensors sit for the current carriage height, arm extension and gripper opening.

use nalgebra::{
    Isometry2, Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3,
};

use super::laser::LaserModel;
use super::rfid::Antenna;
use crate::hal::{AntennaId, CameraCalibration, CameraIntrinsics, Finger, PlanarPose};

/// Fixed geometry of the simulated robot, base frame: EL-E-like by default; see
/// [`SimBody`](super::SimBody) for the classes the simulator builds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyGeometry {
    pub camera: CameraCalibration,
    pub laser: LaserModel,
    /// Where the brightness camera sits (it looks up or forward from there).
    pub brightness_camera: Point3<f64>,
    /// Distance from the base's centre to its front (and back), and to its sides, metres.
    pub base_front: f64,
    pub base_half_width: f64,
    /// Travel of the carriage (hand height), the arm (extension) and the gripper (opening,
    /// radians; wide enough for the entries' 90° drawer and trash-can openings).
    pub carriage_travel: (f64, f64),
    pub arm_travel: (f64, f64),
    pub gripper_travel: (f64, f64),
    /// Length of the fingers beyond the palm, metres.
    pub finger_length: f64,
    /// How far each finger's base sits from the palm's centre line, metres.
    pub knuckle_offset: f64,
}

/// A camera 1.3 m up looking ahead and 12° down; `scale` 1.0 gives 1280×960, 0.25 gives 320×240.
pub fn head_camera(scale: f64) -> CameraCalibration {
    let pitch = 12f64.to_radians();
    let forward = Vector3::new(pitch.cos(), 0.0, -pitch.sin());
    let right = -Vector3::y();
    let down = forward.cross(&right);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[right, down, forward]));
    CameraCalibration {
        intrinsics: CameraIntrinsics {
            width: 1280,
            height: 960,
            fx: 1000.0,
            fy: 1000.0,
            cx: 639.5,
            cy: 479.5,
        }
        .scaled(scale),
        base_from_camera: Isometry3::from_parts(
            Translation3::new(0.05, 0.0, 1.30),
            UnitQuaternion::from_rotation_matrix(&rotation),
        ),
    }
}

impl Default for BodyGeometry {
    fn default() -> Self {
        Self {
            camera: head_camera(0.25),
            laser: LaserModel::default(),
            brightness_camera: Point3::new(0.1, 0.0, 1.4),
            base_front: 0.25,
            base_half_width: 0.25,
            carriage_travel: (0.1, 1.5),
            arm_travel: (0.0, 0.5),
            gripper_travel: (0.0, 1.6),
            finger_length: 0.1,
            knuckle_offset: 0.015,
        }
    }
}

/// Joint positions and poses that change as the robot moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Where the base truly is on the floor, world frame.
    pub world_from_base: PlanarPose,
    /// What odometry believes, in its own frame (identity at start-up).
    pub odometry: PlanarPose,
    pub carriage_height: f64,
    pub arm_extension: f64,
    pub gripper_opening: f64,
}

impl BodyState {
    pub fn at(world_from_base: PlanarPose) -> Self {
        Self {
            world_from_base,
            odometry: Isometry2::identity(),
            carriage_height: 0.8,
            arm_extension: 0.0,
            gripper_opening: 0.0,
        }
    }

    /// The base pose as a 3D isometry (the base frame's origin is on the floor).
    pub fn world_from_base_3d(&self) -> Isometry3<f64> {
        let p = &self.world_from_base;
        Isometry3::new(
            Vector3::new(p.translation.x, p.translation.y, 0.0),
            Vector3::z() * p.rotation.angle(),
        )
    }

    /// The palm's centre, base frame: ahead of the base by the arm's extension, at the carriage's
    /// height.
    pub fn palm(&self, geometry: &BodyGeometry) -> Point3<f64> {
        Point3::new(geometry.base_front + self.arm_extension, 0.0, self.carriage_height)
    }

    /// A fingertip, base frame; the fingers spread sideways as the gripper opens.
    pub fn fingertip(&self, geometry: &BodyGeometry, finger: Finger) -> Point3<f64> {
        let half_angle = self.gripper_opening / 2.0;
        let side = match finger {
            Finger::Left => 1.0,
            Finger::Right => -1.0,
        };
        self.palm(geometry)
            + Vector3::new(
                geometry.finger_length * half_angle.cos(),
                side * (geometry.knuckle_offset + geometry.finger_length * half_angle.sin()),
                0.0,
            )
    }

    /// The four finger antennas, world frame: on each finger one looks forward and one sideways
    /// (EL-E's pairs mounted at 90°).
    pub fn antennas(&self, geometry: &BodyGeometry) -> [Antenna; 4] {
        let world = self.world_from_base_3d();
        let mut out =
            [Antenna { id: AntennaId(0), position: Point3::origin(), boresight: Vector3::x() }; 4];
        for (i, (finger, side)) in
            [(Finger::Left, 1.0), (Finger::Right, -1.0)].into_iter().enumerate()
        {
            let tip = world * self.fingertip(geometry, finger);
            out[2 * i] = Antenna {
                id: AntennaId(2 * i as u8),
                position: tip,
                boresight: world * Vector3::x(),
            };
            out[2 * i + 1] = Antenna {
                id: AntennaId(2 * i as u8 + 1),
                position: tip,
                boresight: world * (Vector3::y() * side),
            };
        }
        out
    }
}
