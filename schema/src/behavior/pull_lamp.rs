//! Pull lamp (paper §IV-B.2.e): grip a lamp's pull chain and pull it down.

use serde::{Deserialize, Serialize};

/// Parameters of `pull_lamp.schema.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PullLampParams {
    /// Close-range alignment back-off, short so the tag sits in the front of the gripper,
    /// metres (0.04..=0.2).
    #[serde(default = "default::alignment_backoff")]
    pub alignment_backoff: f64,
    /// Gripper opening before closing on the chain, degrees (0..=90).
    #[serde(default = "default::gripper_deg")]
    pub gripper_deg: f64,
    /// The force at which closing on the chain stops, newtons (0..=10).
    #[serde(default = "default::grip_force")]
    pub grip_force: f64,
    /// The finger force that stops the downward pull, newtons (0..=20).
    #[serde(default = "default::max_pull_force")]
    pub max_pull_force: f64,
    /// The longest downward pull, metres (0..=0.2).
    #[serde(default = "default::max_pull_distance")]
    pub max_pull_distance: f64,
    /// Smallest change of mean image brightness (fraction of full scale) that counts.
    #[serde(default = "default::brightness_threshold")]
    pub brightness_threshold: f64,
}

impl Default for PullLampParams {
    fn default() -> Self {
        Self {
            alignment_backoff: default::alignment_backoff(),
            gripper_deg: default::gripper_deg(),
            grip_force: default::grip_force(),
            max_pull_force: default::max_pull_force(),
            max_pull_distance: default::max_pull_distance(),
            brightness_threshold: default::brightness_threshold(),
        }
    }
}

mod default {
    pub fn alignment_backoff() -> f64 {
        0.08
    }
    pub fn gripper_deg() -> f64 {
        30.0
    }
    pub fn grip_force() -> f64 {
        3.0
    }
    pub fn max_pull_force() -> f64 {
        10.0
    }
    pub fn max_pull_distance() -> f64 {
        0.07
    }
    pub fn brightness_threshold() -> f64 {
        0.05
    }
}
