//! The person who tells the robot what to do, through the laser-pointer interface (paper §IV-B).

use nalgebra::Point3;

use super::HalError;

/// The paper's two-way action choice: the person points the laser more than 50 cm above the
/// floor (up) or less (down).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VerticalChoice {
    Up,
    Down,
}

/// The operator as the robot perceives them.
pub trait Operator: Send + Sync {
    /// The 3D location the person designated with the laser pointer, in the base frame; `None`
    /// when nobody pointed (a rough estimate: centimetres off along the line of sight).
    fn pointed_target(&self) -> Result<Option<Point3<f64>>, HalError>;

    /// Which of two actions the person chose.
    fn choose_action(&self) -> Result<VerticalChoice, HalError>;

    /// Asks whether the action worked; `None` when the person did not answer.
    fn confirm_success(&self) -> Result<Option<bool>, HalError>;
}
