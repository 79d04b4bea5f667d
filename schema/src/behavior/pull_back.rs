//! Pull back (paper §IV-B.2.c): grasp a towel and back the base off, e.g. to open a drawer.

use serde::{Deserialize, Serialize};

/// Parameters of `pull_back.schema.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PullBackParams {
    /// The force both fingers must feel for the grasp to count, newtons (0..=10).
    #[serde(default = "default::grasp_force")]
    pub grasp_force: f64,
    /// How far the base backs off in one step, metres (0..=0.5).
    #[serde(default = "default::step")]
    pub step: f64,
    /// The finger force that stops pulling (fully open, or stuck), newtons (0..=25).
    #[serde(default = "default::stop_force")]
    pub stop_force: f64,
    /// Below this finger force the grip counts as lost, newtons (0..=10).
    #[serde(default = "default::lost_grip_force")]
    pub lost_grip_force: f64,
    /// How far the thing is expected to move; pulling stops after it, metres (0..=1). Required.
    pub pull_distance: f64,
    /// The fraction of `pull_distance` the gripper must move for success (0..=1).
    #[serde(default = "default::success_ratio")]
    pub success_ratio: f64,
    /// Gripper opening before closing on the towel, degrees (0..=90).
    #[serde(default = "default::gripper_deg")]
    pub gripper_deg: f64,
    /// Close-range alignment back-off after contact, metres (0.04..=0.2).
    #[serde(default = "default::alignment_backoff")]
    pub alignment_backoff: f64,
}

mod default {
    pub fn grasp_force() -> f64 {
        2.0
    }
    pub fn step() -> f64 {
        0.20
    }
    pub fn stop_force() -> f64 {
        12.0
    }
    pub fn lost_grip_force() -> f64 {
        0.5
    }
    pub fn success_ratio() -> f64 {
        0.5
    }
    pub fn gripper_deg() -> f64 {
        90.0
    }
    pub fn alignment_backoff() -> f64 {
        0.12
    }
}
