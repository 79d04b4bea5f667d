//! Who is making a request, once their credential has been checked.

use pps_schema::RobotId;

use crate::auth::Role;
use crate::error::ApiError;

/// An authenticated caller.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Principal {
    pub role: Role,
    /// Shown as `updated_by`: the token's name or the user's login.
    pub name: String,
    /// The robot a robot credential is bound to.
    pub robot: Option<RobotId>,
}

impl Principal {
    /// A robot may act only as itself; caretakers and admins as any robot.
    pub fn require_robot_or_editor(&self, robot: &RobotId) -> Result<(), ApiError> {
        match (&self.role, &self.robot) {
            (Role::Admin | Role::Caretaker, _) => Ok(()),
            (Role::Robot, Some(own)) if own == robot => Ok(()),
            (Role::Robot, own) => Err(ApiError::Forbidden(format!(
                "this robot token is bound to {:?}; it cannot act as {:?}",
                own.as_ref().map_or("", RobotId::as_str),
                robot.as_str()
            ))),
        }
    }
}
