//! The simulated robot: one shared world state behind every `hal` trait, so that what one trait
//! does (the base drives) changes what the others sense (the camera sees from elsewhere).
//!
//! Motions are kinematic for now: the base drives where it is told, with odometry drift; the
//! carriage, arm and gripper move until a fingertip pushes into the scene hard enough, the force
//! coming from a spring model of the contact. Device mechanics (switches that flip, drawers that
//! stick) are not part of this module.

use std::sync::{Arc, Mutex, MutexGuard};

use nalgebra::{
    Isometry2, Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector2, Vector3,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::body::{BodyGeometry, BodyState};
use super::camera::{Exposure, Lighting, render_color, render_gray};
use super::clock::VirtualClock;
use super::noise::gaussian;
use super::rfid::RfidModel;
use super::room::Room;
use crate::hal::{
    Arm, BrightnessCamera, CameraCalibration, CameraIntrinsics, Carriage, ColorCamera, ColorImage,
    Finger, FingerForceTorque, GrayImage, Gripper, HalError, LookDirection, MobileBase, PalmRange,
    PlanarPose, PointCloud, RfidReader, TagRead, TiltSweep, TiltingLaser, Wrench,
};

/// Contact stiffness of a fingertip against the world, newtons per metre.
const CONTACT_STIFFNESS: f64 = 2000.0;
/// Odometry's systematic and random error per metre driven and per radian turned.
const ODOMETRY_SCALE_ERROR: f64 = 0.01;
const ODOMETRY_NOISE: f64 = 0.005;

/// Everything the simulated robot and its world are.
#[derive(Debug)]
pub struct SimState {
    pub room: Room,
    pub lighting: Lighting,
    pub exposure: Exposure,
    pub clock: VirtualClock,
    pub body: BodyState,
    pub geometry: BodyGeometry,
    pub rfid: RfidModel,
    rng: ChaCha8Rng,
}

impl SimState {
    /// Contact force on a fingertip: a spring pushing it out of whatever it is inside.
    fn fingertip_force(&self, finger: Finger) -> Vector3<f64> {
        let world = self.body.world_from_base_3d();
        let tip: Point3<f32> = (world * self.body.fingertip(&self.geometry, finger)).cast();
        match self.room.scene.penetration(&tip) {
            Some((depth, out)) => {
                world.inverse() * (out.cast::<f64>() * f64::from(depth) * CONTACT_STIFFNESS)
            }
            None => Vector3::zeros(),
        }
    }

    fn max_finger_force(&self) -> f64 {
        [Finger::Left, Finger::Right]
            .map(|f| self.fingertip_force(f).norm())
            .into_iter()
            .fold(0.0, f64::max)
    }

    /// Moves a joint toward `goal` in 5 mm steps, stopping where the fingers push harder than
    /// `max_force`; returns where it stopped.
    fn move_joint(
        &mut self,
        goal: f64,
        max_force: f64,
        joint: fn(&mut BodyState) -> &mut f64,
    ) -> f64 {
        let start = *joint(&mut self.body);
        let steps = ((goal - start).abs() / 0.005).ceil().max(1.0) as usize;
        for i in 1..=steps {
            let previous = *joint(&mut self.body);
            *joint(&mut self.body) = start + (goal - start) * i as f64 / steps as f64;
            if self.max_finger_force() > max_force {
                *joint(&mut self.body) = previous;
                break;
            }
        }
        let reached = *joint(&mut self.body);
        self.clock.advance_motion(reached - start, 0.1);
        reached
    }
}

/// The simulated robot; clones share one world.
#[derive(Debug, Clone)]
pub struct SimRobot {
    state: Arc<Mutex<SimState>>,
}

impl SimRobot {
    /// A robot standing at `world_from_base` in `room`, its noise drawn from `seed`.
    pub fn new(room: Room, world_from_base: PlanarPose, seed: u64) -> Self {
        Self::with_geometry(room, world_from_base, BodyGeometry::default(), seed)
    }

    pub fn with_geometry(
        room: Room,
        world_from_base: PlanarPose,
        geometry: BodyGeometry,
        seed: u64,
    ) -> Self {
        let state = SimState {
            room,
            lighting: Lighting::default(),
            exposure: Exposure::default(),
            clock: VirtualClock::default(),
            body: BodyState::at(world_from_base),
            geometry,
            rfid: RfidModel::default(),
            rng: ChaCha8Rng::seed_from_u64(seed),
        };
        Self { state: Arc::new(Mutex::new(state)) }
    }

    /// The world, for tests and the scenario runner to inspect or change (lights, poses).
    pub fn state(&self) -> MutexGuard<'_, SimState> {
        // A panic while holding the lock leaves plain data behind; keep using it.
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl ColorCamera for SimRobot {
    fn calibration(&self) -> CameraCalibration {
        self.state().geometry.camera
    }

    fn capture(&self, flash: bool) -> Result<ColorImage, HalError> {
        let mut s = self.state();
        let camera = s.geometry.camera;
        let world_from_camera = s.body.world_from_base_3d() * camera.base_from_camera;
        let (lighting, exposure) = (s.lighting, s.exposure);
        let SimState { room, rng, clock, .. } = &mut *s;
        clock.advance_motion(1.0, 5.0);
        Ok(render_color(
            room,
            lighting,
            &world_from_camera,
            &camera.intrinsics,
            flash,
            &exposure,
            rng,
        ))
    }
}

impl BrightnessCamera for SimRobot {
    fn capture_light_source(&self, look: LookDirection) -> Result<GrayImage, HalError> {
        let mut s = self.state();
        let pitch_up = match look {
            LookDirection::Up => 70f64.to_radians(),
            LookDirection::Forward => 0.0,
        };
        let forward = Vector3::new(pitch_up.cos(), 0.0, pitch_up.sin());
        let right = -Vector3::y();
        let rotation = Rotation3::from_basis_unchecked(&[right, forward.cross(&right), forward]);
        let base_from_camera = Isometry3::from_parts(
            Translation3::from(s.geometry.brightness_camera.coords),
            UnitQuaternion::from_rotation_matrix(&rotation),
        );
        let world_from_camera = s.body.world_from_base_3d() * base_from_camera;
        let intrinsics =
            CameraIntrinsics { width: 80, height: 60, fx: 60.0, fy: 60.0, cx: 39.5, cy: 29.5 };
        let (lighting, exposure) = (s.lighting, s.exposure);
        let SimState { room, rng, .. } = &mut *s;
        Ok(render_gray(room, lighting, &world_from_camera, &intrinsics, &exposure, rng))
    }
}

impl TiltingLaser for SimRobot {
    fn scan(&self, sweep: &TiltSweep) -> Result<PointCloud, HalError> {
        if !(sweep.step > 0.0 && sweep.to >= sweep.from) {
            return Err(HalError::OutOfRange {
                device: "tilting laser",
                reason: format!("{sweep:?} is not a sweep"),
            });
        }
        let mut s = self.state();
        let world = s.body.world_from_base_3d();
        let laser = s.geometry.laser;
        let SimState { room, rng, clock, .. } = &mut *s;
        // The servo moves at about 1 rad/s.
        clock.advance_motion(sweep.to - sweep.from, 1.0);
        Ok(super::laser::sweep_scan(&room.scene, &world, &laser, sweep, rng))
    }
}

impl RfidReader for SimRobot {
    fn inventory(&self) -> Result<Vec<TagRead>, HalError> {
        let mut s = self.state();
        let antennas = s.body.antennas(&s.geometry);
        let model = s.rfid;
        let SimState { room, rng, clock, .. } = &mut *s;
        clock.advance(std::time::Duration::from_millis(50));
        Ok(model.inventory(&antennas, &room.devices, rng))
    }
}

impl FingerForceTorque for SimRobot {
    fn wrench(&self, finger: Finger) -> Result<Wrench, HalError> {
        let mut s = self.state();
        let force = s.fingertip_force(finger);
        let noise = Vector3::from_fn(|_, _| 0.05 * gaussian(&mut s.rng));
        let lever = s.body.fingertip(&s.geometry, finger) - s.body.palm(&s.geometry);
        Ok(Wrench { force: force + noise, torque: lever.cross(&force) })
    }
}

impl PalmRange for SimRobot {
    fn range(&self) -> Result<Option<f64>, HalError> {
        let mut s = self.state();
        let world = s.body.world_from_base_3d();
        let palm: Point3<f32> = (world * s.body.palm(&s.geometry)).cast();
        let ahead: Vector3<f32> = (world * Vector3::x()).cast();
        let hit = s.room.scene.cast(&palm, &ahead, 0.3);
        Ok(hit.map(|h| (f64::from(h.distance) + 0.003 * gaussian(&mut s.rng)).max(0.0)))
    }
}

impl MobileBase for SimRobot {
    fn pose_estimate(&self) -> Result<PlanarPose, HalError> {
        Ok(self.state().body.odometry)
    }

    fn drive(&self, distance: f64) -> Result<(), HalError> {
        let mut s = self.state();
        let measured = distance * (1.0 + ODOMETRY_SCALE_ERROR)
            + ODOMETRY_NOISE * distance.abs().sqrt() * gaussian(&mut s.rng);
        s.body.world_from_base *= Isometry2::new(Vector2::new(distance, 0.0), 0.0);
        s.body.odometry *= Isometry2::new(Vector2::new(measured, 0.0), 0.0);
        s.clock.advance_motion(distance, 0.3);
        Ok(())
    }

    fn turn(&self, angle: f64) -> Result<(), HalError> {
        let mut s = self.state();
        let measured = angle * (1.0 + ODOMETRY_SCALE_ERROR)
            + ODOMETRY_NOISE * angle.abs().sqrt() * gaussian(&mut s.rng);
        s.body.world_from_base *= Isometry2::new(Vector2::zeros(), angle);
        s.body.odometry *= Isometry2::new(Vector2::zeros(), measured);
        s.clock.advance_motion(angle, 0.5);
        Ok(())
    }
}

fn check_travel(device: &'static str, value: f64, (low, high): (f64, f64)) -> Result<(), HalError> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(())
    } else {
        Err(HalError::OutOfRange {
            device,
            reason: format!("{value} is outside its travel {low}..={high}"),
        })
    }
}

impl Carriage for SimRobot {
    fn height(&self) -> Result<f64, HalError> {
        Ok(self.state().body.carriage_height)
    }

    fn move_to_height(&self, height: f64, max_force: f64) -> Result<f64, HalError> {
        let mut s = self.state();
        check_travel("carriage", height, s.geometry.carriage_travel)?;
        Ok(s.move_joint(height, max_force, |b| &mut b.carriage_height))
    }
}

impl Arm for SimRobot {
    fn extension(&self) -> Result<f64, HalError> {
        Ok(self.state().body.arm_extension)
    }

    fn move_to_extension(&self, extension: f64, max_force: f64) -> Result<f64, HalError> {
        let mut s = self.state();
        check_travel("arm", extension, s.geometry.arm_travel)?;
        Ok(s.move_joint(extension, max_force, |b| &mut b.arm_extension))
    }
}

impl Gripper for SimRobot {
    fn opening(&self) -> Result<f64, HalError> {
        Ok(self.state().body.gripper_opening)
    }

    fn set_opening(&self, angle: f64, max_force: f64) -> Result<f64, HalError> {
        let mut s = self.state();
        check_travel("gripper", angle, s.geometry.gripper_travel)?;
        Ok(s.move_joint(angle, max_force, |b| &mut b.gripper_opening))
    }
}
