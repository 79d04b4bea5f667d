//! Hardware traits: what a robot must provide for the PPS-tag behaviours to run on it.
//!
//! One small trait per capability, in the manner of OpenRR's `arci`: every method takes `&self`
//! (implementations keep their own interior state) and every trait is `Send + Sync`, so a
//! behaviour can hold several capabilities of the same robot at once. Signatures use nalgebra
//! types; units are metres, newtons and radians unless a name says otherwise.
//!
//! Frames: the robot's base frame has x forward, y left, z up, its origin on the floor under the
//! base's centre. Sensors report in the base frame unless a doc comment says otherwise.
//!
//! Nothing here may know whether it is talking to a real robot or the simulator: the simulator
//! is one more implementation of these traits, not a special case above them.

mod base;
mod camera;
mod clock;
mod forward;
mod laser;
mod manipulator;
mod operator;
mod rfid;
mod touch;

pub use base::{MobileBase, PlanarPose};
pub use camera::{
    BrightnessCamera, CameraCalibration, CameraIntrinsics, ColorCamera, ColorImage, GrayImage,
    LookDirection,
};
pub use clock::{Clock, WallClock};
pub(crate) use forward::forward_to;
pub use laser::{PointCloud, TiltSweep, TiltingLaser};
pub use manipulator::{Arm, Carriage, Gripper};
pub use operator::{Operator, VerticalChoice};
pub use rfid::{AntennaId, RfidReader, TagRead};
pub use touch::{Finger, FingerForceTorque, PalmRange, Wrench};

/// Why a device could not do what was asked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HalError {
    /// The device is not connected or not powered.
    #[error("{device} is unavailable: {reason}")]
    Unavailable { device: &'static str, reason: String },
    /// The request is outside what the device can do (a height above the carriage's travel).
    #[error("{device} cannot do that: {reason}")]
    OutOfRange { device: &'static str, reason: String },
    /// The device tried and failed (a timeout, a driver error).
    #[error("{device} failed: {reason}")]
    Failed { device: &'static str, reason: String },
}
