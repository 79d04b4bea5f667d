//! Light switch (paper §IV-B.2.b): flip a toggle with the carriage, or press a rocker.

use serde::{Deserialize, Serialize};

/// Parameters of `light_switch.schema.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightSwitchParams {
    #[serde(default)]
    pub motion: SwitchMotion,
    /// For [`SwitchMotion::Flip`]: which way the carriage sweeps the toggle (required there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<SweepDirection>,
    /// Where the gripper starts, metres above (+) or below (−) the tag's centre (−0.15..=0.15).
    #[serde(default)]
    pub height_offset: f64,
    /// Press: the force at which pressing stops, newtons (0..=20).
    #[serde(default = "default::force_threshold")]
    pub force_threshold: f64,
    /// Flip: the force that means the fingers touched the wall, newtons (0..=10).
    #[serde(default = "default::contact_force")]
    pub contact_force: f64,
    /// Flip: back-off from the wall after contact, clearing the plate, metres (0..=0.1).
    #[serde(default = "default::wall_clearance")]
    pub wall_clearance: f64,
    /// Flip: the force on the gripper that stops the sweep, newtons (0..=20).
    #[serde(default = "default::max_carriage_force")]
    pub max_carriage_force: f64,
    /// Flip: the longest sweep of the carriage, metres (0..=0.3).
    #[serde(default = "default::max_travel")]
    pub max_travel: f64,
    /// Gripper opening, degrees (0 closed ..= 90 fully open).
    #[serde(default = "default::gripper_deg")]
    pub gripper_deg: f64,
    /// Close-range alignment back-off after contact, metres (0.04..=0.2).
    #[serde(default = "default::alignment_backoff")]
    pub alignment_backoff: f64,
    /// Smallest change of mean image brightness (fraction of full scale) that counts.
    #[serde(default = "default::brightness_threshold")]
    pub brightness_threshold: f64,
}

impl LightSwitchParams {
    /// The largest force the chosen motion commands, newtons.
    pub fn peak_force(&self) -> f64 {
        match self.motion {
            SwitchMotion::Press => self.force_threshold,
            SwitchMotion::Flip => self.contact_force.max(self.max_carriage_force),
        }
    }
}

impl Default for LightSwitchParams {
    /// Press the centre of the tag, as the paper's ADA switch entry does with no offset.
    fn default() -> Self {
        Self {
            motion: SwitchMotion::default(),
            direction: None,
            height_offset: 0.0,
            force_threshold: default::force_threshold(),
            contact_force: default::contact_force(),
            wall_clearance: default::wall_clearance(),
            max_carriage_force: default::max_carriage_force(),
            max_travel: default::max_travel(),
            gripper_deg: default::gripper_deg(),
            alignment_backoff: default::alignment_backoff(),
            brightness_threshold: default::brightness_threshold(),
        }
    }
}

/// How the switch is operated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SwitchMotion {
    /// Sweep a toggle with the carriage (the paper's flip-type switch).
    Flip,
    /// Poke a rocker at `height_offset` (the paper's ADA switch and its Fig. 4 entry).
    #[default]
    Press,
}

/// Which way the carriage sweeps a toggle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepDirection {
    Up,
    Down,
}

mod default {
    pub fn force_threshold() -> f64 {
        3.0
    }
    pub fn contact_force() -> f64 {
        2.0
    }
    pub fn wall_clearance() -> f64 {
        0.02
    }
    pub fn max_carriage_force() -> f64 {
        12.0
    }
    pub fn max_travel() -> f64 {
        0.15
    }
    pub fn gripper_deg() -> f64 {
        10.0
    }
    pub fn alignment_backoff() -> f64 {
        0.10
    }
    pub fn brightness_threshold() -> f64 {
        0.05
    }
}
