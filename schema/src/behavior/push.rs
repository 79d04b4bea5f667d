//! Push (paper §IV-B.2.d): push along the surface normal, e.g. to close a drawer.

use serde::{Deserialize, Serialize};

/// Parameters of `push.schema.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PushParams {
    /// The force that means the gripper touched the surface, newtons (0..=10).
    #[serde(default = "default::contact_force")]
    pub contact_force: f64,
    /// The force that stops pushing (closed, or stuck), newtons (0..=25).
    #[serde(default = "default::stop_force")]
    pub stop_force: f64,
    /// How far to push with the base after contact, metres (0..=1). Required.
    pub push_distance: f64,
    /// Success when the change is `location`: the fraction of `push_distance` moved (0..=1).
    #[serde(default = "default::success_ratio")]
    pub success_ratio: f64,
    /// Success when the change is `overall_brightness`: the smallest change of mean image
    /// brightness (fraction of full scale).
    #[serde(default = "default::brightness_threshold")]
    pub brightness_threshold: f64,
    /// Gripper opening while pushing, degrees (0 closed to poke ..= 90 open for a drawer front).
    #[serde(default = "default::gripper_deg")]
    pub gripper_deg: f64,
    /// Close-range alignment back-off after contact, metres (0.04..=0.2).
    #[serde(default = "default::alignment_backoff")]
    pub alignment_backoff: f64,
}

mod default {
    pub fn contact_force() -> f64 {
        2.0
    }
    pub fn stop_force() -> f64 {
        12.0
    }
    pub fn success_ratio() -> f64 {
        0.5
    }
    pub fn brightness_threshold() -> f64 {
        0.05
    }
    pub fn gripper_deg() -> f64 {
        90.0
    }
    pub fn alignment_backoff() -> f64 {
        0.10
    }
}
