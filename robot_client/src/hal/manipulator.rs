//! The arm of a robot like EL-E: a carriage that sets the hand's height, an arm that extends it
//! forward and a one-degree-of-freedom gripper.

use super::HalError;

/// The linear carriage that moves the arm up and down.
pub trait Carriage: Send + Sync {
    /// Height of the hand above the floor, metres.
    fn height(&self) -> Result<f64, HalError>;

    /// Moves the hand to `height` metres above the floor, stopping early when the force on the
    /// fingers exceeds `max_force` newtons. Returns the height reached.
    fn move_to_height(&self, height: f64, max_force: f64) -> Result<f64, HalError>;
}

/// The arm's forward extension.
pub trait Arm: Send + Sync {
    /// How far the hand is extended ahead of the base's front, metres.
    fn extension(&self) -> Result<f64, HalError>;

    /// The farthest extension the arm reaches, metres.
    fn farthest(&self) -> f64;

    /// Extends (or retracts) the hand to `extension` metres, stopping early when the force on the
    /// fingers exceeds `max_force` newtons. Returns the extension reached.
    fn move_to_extension(&self, extension: f64, max_force: f64) -> Result<f64, HalError>;
}

/// The gripper: one opening angle for both fingers.
pub trait Gripper: Send + Sync {
    /// Opening angle between the fingers, radians (0 is closed).
    fn opening(&self) -> Result<f64, HalError>;

    /// The widest opening the gripper reaches, radians.
    fn widest(&self) -> f64;

    /// Sets the opening angle, radians, stopping early when the grip force exceeds `max_force`
    /// newtons. Returns the angle reached.
    fn set_opening(&self, angle: f64, max_force: f64) -> Result<f64, HalError>;
}
