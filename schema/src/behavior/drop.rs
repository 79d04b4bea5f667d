//! Drop (paper §IV-B.2.f): release the held object above a tagged container.

use serde::{Deserialize, Serialize};

/// Parameters of `drop.schema.json`. Drop has no close-range alignment: the held object
/// blocks the hand camera.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DropParams {
    /// How far from the drop point the base stops, metres (0.2..=1).
    #[serde(default = "default::standoff")]
    pub standoff: f64,
    /// How high above the container's rim the object is released, metres (0..=0.5).
    #[serde(default = "default::release_height")]
    pub release_height: f64,
    /// Gripper opening to release the object, degrees (0..=90).
    #[serde(default = "default::gripper_deg")]
    pub gripper_deg: f64,
    /// A finger force above this after releasing means the object is still held, newtons.
    #[serde(default = "default::still_held_force")]
    pub still_held_force: f64,
    /// Something nearer the palm range sensor than this after releasing means the object is
    /// still held, metres.
    #[serde(default = "default::still_held_range")]
    pub still_held_range: f64,
}

impl Default for DropParams {
    fn default() -> Self {
        Self {
            standoff: default::standoff(),
            release_height: default::release_height(),
            gripper_deg: default::gripper_deg(),
            still_held_force: default::still_held_force(),
            still_held_range: default::still_held_range(),
        }
    }
}

mod default {
    pub fn standoff() -> f64 {
        0.45
    }
    pub fn release_height() -> f64 {
        0.10
    }
    pub fn gripper_deg() -> f64 {
        60.0
    }
    pub fn still_held_force() -> f64 {
        0.3
    }
    pub fn still_held_range() -> f64 {
        0.05
    }
}
