//! Who is making a request, once their credential has been checked.

use pps_schema::RobotId;

use crate::error::ApiError;
use crate::identity::Role;

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
    /// The robot this credential is bound to, as messages name it (`""` for none).
    pub fn robot_name(&self) -> &str {
        self.robot.as_ref().map_or("", RobotId::as_str)
    }

    /// The robot a robot credential acts for; every robot token is bound to one.
    pub fn own_robot(&self) -> Result<&RobotId, ApiError> {
        self.robot.as_ref().ok_or_else(|| {
            ApiError::Internal(anyhow::anyhow!("a robot credential without a robot id"))
        })
    }

    /// A robot may act only as itself; caretakers and admins as any robot.
    pub fn require_robot_or_editor(&self, robot: &RobotId) -> Result<(), ApiError> {
        match (&self.role, &self.robot) {
            (Role::Admin | Role::Caretaker, _) => Ok(()),
            (Role::Robot, Some(own)) if own == robot => Ok(()),
            (Role::Robot, _) => Err(ApiError::Forbidden(format!(
                "this robot token is bound to {:?}; it cannot act as {:?}",
                self.robot_name(),
                robot.as_str()
            ))),
        }
    }
}
