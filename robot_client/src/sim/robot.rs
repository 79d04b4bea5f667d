//! The simulated robot: one shared world state behind every `hal` trait, so that what one trait
//! does (the base drives) changes what the others sense (the camera sees from elsewhere).
//!
//! Every motion (base, carriage, arm, gripper) is stepped against the devices' mechanics and the
//! rigid room (see `motion`), so contact is felt mid-move and force limits stop motions where a
//! robot's would stop; the base drives with odometry drift and stops on its own safety force.

use std::sync::{Arc, Mutex, MutexGuard};

use nalgebra::{
    Isometry2, Isometry3, Point2, Point3, Rotation3, Translation3, UnitQuaternion, Vector2, Vector3,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::body::{BodyGeometry, BodyState};
use super::camera::{Exposure, render_color, render_gray};
use super::clock::VirtualClock;
use super::mechanics::{DeviceMechanics, HeldObject, OBJECT_RANGE};
use super::noise::gaussian;
use super::rfid::RfidModel;
use super::room::Room;
use super::scenario::{DeviceTruth, Scenario};
use super::sim_body::SimBody;
use crate::hal::{
    Arm, BrightnessCamera, CameraCalibration, CameraIntrinsics, Carriage, ColorCamera, ColorImage,
    Finger, FingerForceTorque, GrayImage, Gripper, HalError, LookDirection, MobileBase, PalmRange,
    PlanarPose, PointCloud, RfidReader, TagRead, TiltSweep, TiltingLaser, Wrench,
};

/// Joint steps between contact checks: a millimetre of carriage or arm, a few milliradians of
/// gripper or base turn, five millimetres of base travel.
const JOINT_STEP: f64 = 0.001;
const GRIPPER_STEP: f64 = 0.005;
const DRIVE_STEP: f64 = 0.005;
const TURN_STEP: f64 = 0.005;
/// The base's own safety: it stops when a finger is pushed harder than this, newtons.
pub const BASE_SAFETY_FORCE: f64 = 30.0;
/// Odometry's systematic and random error per metre driven and per radian turned.
const ODOMETRY_SCALE_ERROR: f64 = 0.01;
const ODOMETRY_NOISE: f64 = 0.005;
/// Noise of each force component the finger sensors report, newtons.
const FORCE_NOISE: f64 = 0.05;

/// Everything the simulated robot and its world are.
#[derive(Debug)]
pub struct SimState {
    pub room: Room,
    pub devices: DeviceMechanics,
    pub exposure: Exposure,
    pub clock: VirtualClock,
    pub body: BodyState,
    pub geometry: BodyGeometry,
    pub rfid: RfidModel,
    /// Every pose the base has truly stood in, world frame, oldest first: where it started, and
    /// each step of its drives (5 mm) and turns (5 mrad). For tests that check where the robot
    /// went; behaviours see only odometry.
    pub base_path: Vec<PlanarPose>,
    /// Where in `base_path` the base stood at the last RFID inventory, if there was one.
    pub read_from: Option<usize>,
    /// Every state the body has truly been in, oldest first: where it started, and each step
    /// of every motion of its base, carriage, arm and gripper. For tests that check what the
    /// whole robot swept.
    pub body_path: Vec<BodyState>,
    /// Where in `body_path` the body stood at the last RFID inventory, if there was one.
    pub body_read_from: Option<usize>,
    /// Someone who steps in behind the robot once it reads a tag, and where they stand once
    /// they have (world frame): see [`Scenario::person_behind`].
    pub(super) person_behind: Option<f64>,
    pub person: Option<Point2<f64>>,
    pub(super) rng: ChaCha8Rng,
}

/// The simulated robot; clones share one world.
#[derive(Debug, Clone)]
pub struct SimRobot {
    state: Arc<Mutex<SimState>>,
}

impl SimRobot {
    /// A robot standing at `world_from_base` in `room`, its noise drawn from `seed`, in the
    /// paper's office: [`Scenario::office`], the ceiling light on and nothing broken.
    pub fn new(room: Room, world_from_base: PlanarPose, seed: u64) -> Self {
        Self::with_geometry(room, world_from_base, BodyGeometry::default(), seed)
    }

    /// A robot as [`SimRobot::new`] in a room whose devices start as `scenario` says.
    pub fn with_scenario(
        room: Room,
        world_from_base: PlanarPose,
        seed: u64,
        scenario: Scenario,
    ) -> Self {
        Self::of_class(room, world_from_base, seed, scenario, SimBody::ElE)
    }

    /// A robot of the class `body` as [`SimRobot::with_scenario`].
    pub fn of_class(
        room: Room,
        world_from_base: PlanarPose,
        seed: u64,
        scenario: Scenario,
        body: SimBody,
    ) -> Self {
        Self::build(room, world_from_base, body.geometry(), body.exposure(), seed, scenario)
    }

    pub fn with_geometry(
        room: Room,
        world_from_base: PlanarPose,
        geometry: BodyGeometry,
        seed: u64,
    ) -> Self {
        Self::build(room, world_from_base, geometry, Exposure::default(), seed, Scenario::office())
    }

    fn build(
        room: Room,
        world_from_base: PlanarPose,
        geometry: BodyGeometry,
        exposure: Exposure,
        seed: u64,
        scenario: Scenario,
    ) -> Self {
        let mut body = BodyState::at(world_from_base);
        if scenario.object_in_hand {
            body.gripper_opening = HeldObject::holding_opening(&geometry);
        }
        let mut state = SimState {
            devices: DeviceMechanics::new(&room, &scenario),
            room,
            exposure,
            clock: VirtualClock::default(),
            body,
            geometry,
            rfid: RfidModel::default(),
            base_path: vec![world_from_base],
            read_from: None,
            body_path: vec![body],
            body_read_from: None,
            person_behind: scenario.person_behind,
            person: None,
            rng: ChaCha8Rng::seed_from_u64(seed),
        };
        state.show_moving_parts();
        Self { state: Arc::new(Mutex::new(state)) }
    }

    /// What the devices truly are. For tests and the experiment's bookkeeping only: behaviours
    /// must see the world through the hardware traits.
    pub fn truth(&self) -> DeviceTruth {
        self.state().devices.truth()
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
        let (lighting, exposure) = (s.devices.lighting(), s.exposure);
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
        let (lighting, exposure) = (s.devices.lighting(), s.exposure);
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
        s.read_from = Some(s.base_path.len() - 1);
        s.body_read_from = Some(s.body_path.len() - 1);
        if s.person.is_none()
            && let Some(behind) = s.person_behind
        {
            s.person = Some(back_along(&s.base_path, behind));
        }
        let SimState { room, rng, clock, .. } = &mut *s;
        clock.advance(std::time::Duration::from_millis(50));
        Ok(model.inventory(&antennas, &room.devices, rng))
    }
}

impl FingerForceTorque for SimRobot {
    fn wrench(&self, finger: Finger) -> Result<Wrench, HalError> {
        let mut s = self.state();
        let index = match finger {
            Finger::Left => 0,
            Finger::Right => 1,
        };
        let base_from_world = s.body.world_from_base_3d().inverse();
        let force = base_from_world * s.finger_forces()[index];
        let noise = Vector3::from_fn(|_, _| FORCE_NOISE * gaussian(&mut s.rng));
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
        let mut nearest = s.room.scene.cast(&palm, &ahead, 0.3).map(|h| f64::from(h.distance));
        if s.devices.object_in_hand() {
            nearest = Some(nearest.map_or(OBJECT_RANGE, |d| d.min(OBJECT_RANGE)));
        }
        Ok(nearest.map(|d| (d + 0.003 * gaussian(&mut s.rng)).max(0.0)))
    }
}

impl MobileBase for SimRobot {
    fn pose_estimate(&self) -> Result<PlanarPose, HalError> {
        Ok(self.state().body.odometry)
    }

    fn drive(&self, distance: f64) -> Result<(), HalError> {
        check_finite("base", distance)?;
        let mut s = self.state();
        let start = s.body.world_from_base;
        let steps = (distance.abs() / DRIVE_STEP).ceil() as usize;
        let reached = s.move_body(steps, BASE_SAFETY_FORCE, false, |body, f| {
            body.world_from_base = start * Isometry2::new(Vector2::new(distance * f, 0.0), 0.0);
        });
        let driven = distance * reached;
        let measured = driven * (1.0 + ODOMETRY_SCALE_ERROR)
            + ODOMETRY_NOISE * driven.abs().sqrt() * gaussian(&mut s.rng);
        s.body.odometry *= Isometry2::new(Vector2::new(measured, 0.0), 0.0);
        s.clock.advance_motion(driven, 0.3);
        Ok(())
    }

    fn turn(&self, angle: f64) -> Result<(), HalError> {
        check_finite("base", angle)?;
        let mut s = self.state();
        let start = s.body.world_from_base;
        let steps = (angle.abs() / TURN_STEP).ceil() as usize;
        let reached = s.move_body(steps, BASE_SAFETY_FORCE, false, |body, f| {
            body.world_from_base = start * Isometry2::new(Vector2::zeros(), angle * f);
        });
        let turned = angle * reached;
        let measured = turned * (1.0 + ODOMETRY_SCALE_ERROR)
            + ODOMETRY_NOISE * turned.abs().sqrt() * gaussian(&mut s.rng);
        s.body.odometry *= Isometry2::new(Vector2::zeros(), measured);
        s.clock.advance_motion(turned, 0.5);
        Ok(())
    }
}

/// The point `distance` metres back along `path` from its last pose, measured along the way the
/// base's centre went; its start where the path is shorter.
fn back_along(path: &[PlanarPose], distance: f64) -> Point2<f64> {
    let mut left = distance;
    for leg in path.windows(2).rev() {
        let (from, to) = (leg[0].translation.vector, leg[1].translation.vector);
        let length = (to - from).norm();
        if length >= left && length > 0.0 {
            return Point2::from(to + (from - to) * (left / length));
        }
        left -= length;
    }
    Point2::from(path[0].translation.vector)
}

fn check_finite(device: &'static str, value: f64) -> Result<(), HalError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(HalError::OutOfRange { device, reason: format!("{value} is not a distance") })
    }
}

/// Moves one joint of the arm to `goal` in steps of `step`, force-limited; returns where it got.
/// With `yielding_arm` (the gripper), the arm gives way to fingertips closing against a surface.
fn move_joint(
    s: &mut SimState,
    goal: f64,
    step: f64,
    max_force: f64,
    yielding_arm: bool,
    joint: fn(&mut BodyState) -> &mut f64,
) -> f64 {
    let start = *joint(&mut s.body);
    let steps = ((goal - start).abs() / step).ceil() as usize;
    s.move_body(steps, max_force, yielding_arm, |body, f| {
        *joint(body) = start + (goal - start) * f
    });
    let reached = *joint(&mut s.body);
    s.clock.advance_motion(reached - start, 0.1);
    reached
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
        Ok(move_joint(&mut s, height, JOINT_STEP, max_force, false, |b| &mut b.carriage_height))
    }
}

impl Arm for SimRobot {
    fn extension(&self) -> Result<f64, HalError> {
        Ok(self.state().body.arm_extension)
    }

    fn farthest(&self) -> f64 {
        self.state().geometry.arm_travel.1
    }

    fn move_to_extension(&self, extension: f64, max_force: f64) -> Result<f64, HalError> {
        let mut s = self.state();
        check_travel("arm", extension, s.geometry.arm_travel)?;
        Ok(move_joint(&mut s, extension, JOINT_STEP, max_force, false, |b| &mut b.arm_extension))
    }
}

impl Gripper for SimRobot {
    fn opening(&self) -> Result<f64, HalError> {
        Ok(self.state().body.gripper_opening)
    }

    fn widest(&self) -> f64 {
        self.state().geometry.gripper_travel.1
    }

    fn set_opening(&self, angle: f64, max_force: f64) -> Result<f64, HalError> {
        let mut s = self.state();
        check_travel("gripper", angle, s.geometry.gripper_travel)?;
        Ok(move_joint(&mut s, angle, GRIPPER_STEP, max_force, true, |b| &mut b.gripper_opening))
    }
}
