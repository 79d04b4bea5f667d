//! The simulator: a seeded, deterministic room with the paper's five tagged devices, rendered
//! for the robot's sensors, and a robot body that implements every [`crate::hal`] trait.
//!
//! - [`Room`]: walls, the five devices with their EPCs, wooden furniture, lights.
//! - [`SimRobot`]: the body and its sensors: camera images by ray casting every pixel, tilting
//!   laser clouds by ray casting every beam, RFID reads from a path-loss model, contact forces
//!   from a spring model; odometry with drift. Time is a [`VirtualClock`]; nothing sleeps.
//! - [`capture_scene`]: the robot placed as in the paper's trials, recording image, cloud,
//!   calibration and the operator's target, exportable as PNG, PLY and JSON.
//!
//! The simulator is only one more implementation of the hardware traits: perception and
//! navigation never reach into it, and it never uses them.

mod body;
mod camera;
mod capture;
mod clock;
mod laser;
mod noise;
mod operator;
mod rfid;
mod robot;
mod room;
mod scene;

pub use body::{BodyGeometry, BodyState, head_camera};
pub use camera::{Exposure, Lighting, render_color, render_gray};
pub use capture::{CaptureSettings, SceneCapture, StartDirection, capture_scene, start_pose};
pub use clock::VirtualClock;
pub use laser::{LaserModel, sweep_scan};
pub use operator::{OperatorScript, SimOperator};
pub use rfid::{Antenna, RfidModel};
pub use robot::{SimRobot, SimState};
pub use room::{Device, DeviceKind, Room, RoomOptions};
pub use scene::{Hit, LightSource, Part, Scene, Surface, WallFrame};
