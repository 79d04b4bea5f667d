//! The simulator: a seeded, deterministic room with the paper's five tagged devices, rendered
//! for the robot's sensors, and a robot body that implements every [`crate::hal`] trait.
//!
//! - [`Room`]: walls, the five devices with their EPCs, wooden furniture, lights.
//! - [`SimRobot`]: the body and its sensors: camera images by ray casting every pixel, tilting
//!   laser clouds by ray casting every beam, RFID reads from a path-loss model, contact forces
//!   from a spring model; odometry with drift. Time is a [`VirtualClock`]; nothing sleeps.
//! - The devices' mechanics: the flip and rocker switches toggling the ceiling light, the lamp's
//!   pull chain, the drawer on its slide with its towel, the held object and the trash can, all
//!   moved only by the fingers' contacts. A [`Scenario`] sets their initial state and injected
//!   failures; [`SimRobot::truth`] reports them for tests and bookkeeping, never for behaviours.
//! - [`capture_scene`]: the robot placed as in the paper's trials, recording image, cloud,
//!   calibration and the operator's target, exportable as PNG, PLY and JSON.
//!
//! The simulator is only one more implementation of the hardware traits: perception and
//! navigation never reach into it, and it never uses them.

mod body;
mod camera;
mod capture;
mod clock;
mod depth_camera;
mod laser;
mod mechanics;
mod motion;
mod noise;
mod operator;
mod rfid;
mod robot;
mod room;
mod scenario;
mod scene;
mod sim_body;
mod trial_clock;

pub use body::{BodyGeometry, BodyState, head_camera};
pub use camera::{Exposure, Lighting, render_color, render_gray};
pub use capture::{
    CaptureSettings, SceneCapture, StartDirection, capture_scene, start_pose, start_pose_at_angle,
};
pub use clock::VirtualClock;
pub use depth_camera::AlignedDepth;
pub use laser::{LaserModel, sweep_scan};
#[cfg(test)]
pub(crate) use noise::gaussian;
pub use operator::{OperatorScript, SimOperator};
pub use rfid::{Antenna, RfidModel};
pub use robot::{SimRobot, SimState};
pub use room::{Device, DeviceKind, Room, RoomOptions};
pub use scenario::{DeviceTruth, Scenario};
pub use scene::{Hit, LightSource, Part, Scene, Surface, WallFrame, hsv_to_srgb};
pub use sim_body::SimBody;
pub use trial_clock::SimClock;
