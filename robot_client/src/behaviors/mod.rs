//! The manipulation behaviours of the paper's §IV-B.2, one file each, in the paper's order:
//! [`close_range_alignment`], [`operate_light_switch`], [`pull_back`], [`push`], [`pull_lamp`],
//! [`drop_object`].
//!
//! Each behaviour is generic over the `hal` traits it needs, takes its parameters from the
//! effective entry (the registry has already merged the robot's overrides and learned values),
//! runs its own success detector, and returns a [`BehaviorReport`]: the outcome, what the
//! decision rested on, its measurements, the finger forces sampled while it ran and the steps it
//! took. Behaviours see the world only through the traits: never the simulator's state.

mod alignment;
mod drop;
mod force;
mod light_check;
mod light_switch;
mod motion;
mod pull_back;
mod pull_lamp;
mod push;

use pps_schema::{ForceSample, Outcome};
use serde_json::{Map, Value};

pub use alignment::{Alignment, AlignmentParams, Contact, close_range_alignment};
pub use drop::{DropGeometry, drop_object};
pub use force::{FingerForces, ForceRecorder};
pub use light_switch::operate_light_switch;
pub use motion::{Hand, RobotBody};
pub use pull_back::pull_back;
pub use pull_lamp::pull_lamp;
pub use push::push;

/// The state change the person asked for, as far as a light is concerned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WantedLight {
    On,
    Off,
    /// Any change counts (an action that is neither `on` nor `off`).
    Changed,
}

impl WantedLight {
    /// From the entry's action name.
    pub fn for_action(action: &str) -> Self {
        match action {
            "on" => Self::On,
            "off" => Self::Off,
            _ => Self::Changed,
        }
    }
}

/// What one behaviour did and what it concluded.
#[derive(Debug, Clone, PartialEq)]
pub struct BehaviorReport {
    /// The behaviour's own detector: success or failure (errors are the caller's to record).
    pub outcome: Outcome,
    /// What the decision rested on (the trial's `detector`).
    pub detector: Map<String, Value>,
    /// Behaviour-specific measurements (the trial's `measurements`), e.g. `displacement`.
    pub measurements: Map<String, Value>,
    /// Finger force-torque samples taken while it ran.
    pub forces: Vec<ForceSample>,
    /// The steps taken, in order, for a person reading the task's report.
    pub steps: Vec<String>,
}

/// Collects a behaviour's evidence as it runs.
#[derive(Debug, Default)]
pub struct Evidence {
    detector: Map<String, Value>,
    measurements: Map<String, Value>,
    steps: Vec<String>,
}

impl Evidence {
    /// Notes a step taken.
    pub fn step(&mut self, text: impl Into<String>) {
        self.steps.push(text.into());
    }

    /// Records something the success decision rests on.
    pub fn detector(&mut self, key: &str, value: impl Into<Value>) {
        self.detector.insert(key.to_owned(), value.into());
    }

    /// Records a measurement of the behaviour.
    pub fn measure(&mut self, key: &str, value: impl Into<Value>) {
        self.measurements.insert(key.to_owned(), value.into());
    }

    /// Ends the behaviour with `success` as the detector decided.
    pub fn finish(self, success: bool, forces: ForceRecorder<'_>) -> BehaviorReport {
        BehaviorReport {
            outcome: if success { Outcome::Success } else { Outcome::Failure },
            detector: self.detector,
            measurements: self.measurements,
            forces: forces.into_samples(),
            steps: self.steps,
        }
    }
}

/// Rounds to a millimetre (or a thousandth), so the evidence reads cleanly.
pub(crate) fn milli(value: f64) -> f64 {
    (value * 1000.0).round() / 1000.0
}
