//! A robot known to the registry: what it can run and within which limits.

use serde::{Deserialize, Serialize};
use time::OffsetDateTime;

use crate::behavior::BehaviorKind;
use crate::robot_id::RobotId;

/// A robot, as an admin PUTs it; `last_seen` is the registry's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Robot {
    pub id: RobotId,
    /// The class whose overrides and learned values it shares (same grammar as ids); `None`
    /// until an admin sets it.
    #[serde(default)]
    pub class: Option<RobotId>,
    pub name: String,
    /// The behaviours it can run, each once.
    pub capabilities: Vec<BehaviorKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<RobotLimits>,
    /// Read-only: when it last called the registry.
    #[serde(
        default,
        with = "time::serde::rfc3339::option",
        skip_serializing_if = "Option::is_none"
    )]
    pub last_seen: Option<OffsetDateTime>,
}

impl Robot {
    pub fn can_run(&self, behavior: BehaviorKind) -> bool {
        self.capabilities.contains(&behavior)
    }
}

/// What a robot can safely do; an action beyond these is unavailable to it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RobotLimits {
    /// The largest force any behaviour may command on its fingers, newtons.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_force: Option<f64>,
    /// The highest point above the floor the gripper reaches, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_reach_height: Option<f64>,
}
