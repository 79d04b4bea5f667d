//! The mobile base and its odometry.

use nalgebra::{Isometry2, Vector2};

use super::HalError;

/// A pose on the floor: x, y in metres and yaw in radians, as an isometry.
pub type PlanarPose = Isometry2<f64>;

/// A mobile base that reports its pose by odometry. Moves are relative to where the base is;
/// they return when the move is done (or stopped by the base's own safety).
pub trait MobileBase: Send + Sync {
    /// The pose estimated by odometry since start-up. It drifts; callers re-perceive when it
    /// matters.
    fn pose_estimate(&self) -> Result<PlanarPose, HalError>;

    /// Drives straight by `distance` metres (negative drives backwards).
    fn drive(&self, distance: f64) -> Result<(), HalError>;

    /// Turns in place by `angle` radians (positive is counter-clockwise, toward +y).
    fn turn(&self, angle: f64) -> Result<(), HalError>;

    /// Moves by `translation` (metres, in the base frame as it is now) and then turns by `yaw`
    /// radians; the holonomic-looking move a differential base makes as turn, drive, turn.
    fn move_relative(&self, translation: Vector2<f64>, yaw: f64) -> Result<(), HalError> {
        let distance = translation.norm();
        if distance > 1e-6 {
            let heading = translation.y.atan2(translation.x);
            self.turn(heading)?;
            self.drive(distance)?;
            self.turn(yaw - heading)
        } else {
            self.turn(yaw)
        }
    }
}
