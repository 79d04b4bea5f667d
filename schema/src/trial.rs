//! A trial: one attempt by a robot to perform an action, recorded in the registry.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use time::OffsetDateTime;
use uuid::Uuid;

use crate::entry::TagSize;
use crate::epc::Epc;
use crate::robot_id::RobotId;

/// The most force-torque samples one trial may carry (the schema's `maxItems`): 5 000 is
/// 50 s of both fingers at 50 Hz, longer than any behaviour runs, and fits the API's 1 MiB
/// request limit even with torques.
pub const MAX_FORCE_SAMPLES: usize = 5_000;

/// One attempt, as a robot PUTs it; `received_at` and `seq` are the registry's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trial {
    /// Chosen by the robot, so a retried upload is stored once.
    pub id: Uuid,
    pub epc: Epc,
    pub robot: RobotId,
    /// The action performed, e.g. `on`.
    pub action: String,
    /// The key in the entry's `behaviors` that ran, e.g. `push_top`.
    pub behavior: String,
    #[serde(with = "time::serde::rfc3339")]
    pub started_at: OffsetDateTime,
    #[serde(with = "time::serde::rfc3339")]
    pub finished_at: OffsetDateTime,
    pub outcome: Outcome,
    /// The person's answer; `None` (JSON null) while nobody has answered.
    #[serde(default)]
    pub confirmed: Option<bool>,
    /// What the success decision rested on (free-form).
    #[serde(default)]
    pub detector: Map<String, Value>,
    #[serde(default)]
    pub forces: Vec<ForceSample>,
    /// Behaviour-specific measurements (free-form).
    #[serde(default)]
    pub measurements: Map<String, Value>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_pose: Option<StartPose>,
    /// Why the attempt was made; real use is not written, so a robot's trial reads the same to
    /// a registry that predates the field.
    #[serde(default, skip_serializing_if = "Purpose::is_use")]
    pub purpose: Purpose,
    /// The detected tag's colour, sent once its EPC was read (so the pixels are that tag).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tag_color: Option<TagColor>,
    /// The detected tag's size on the surface behind it, sent on the same condition as
    /// `tag_color`: the registry learns the size of a tag whose entry has none from it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tag_size: Option<TagSize>,
    /// Read-only: when the registry received the trial.
    #[serde(
        default,
        with = "time::serde::rfc3339::option",
        skip_serializing_if = "Option::is_none"
    )]
    pub received_at: Option<OffsetDateTime>,
    /// Read-only: the trial's place in the registry's arrival order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seq: Option<u64>,
}

/// Statistics of the pixels a robot took for a tag whose EPC its fingers then read: what the
/// registry learns the tag's colour, and the household's, from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TagColor {
    /// How many pixels the statistics are over.
    pub pixels: u64,
    /// 5th, 50th and 95th percentiles of hue, degrees in 0..360, along the circle from the
    /// side opposite the median: the 5th is above the 95th when the hues wrap through 0.
    pub hue_deg: [f64; 3],
    /// 5th, 50th and 95th percentiles of saturation, 0..=1.
    pub saturation: [f64; 3],
    /// 5th, 50th and 95th percentiles of value, 0..=1.
    pub value: [f64; 3],
    /// Median value of the whole picture, 0..=1: how brightly the scene was lit.
    pub light_level: f64,
}

/// The robot's own verdict on an attempt.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// The success detector saw the expected change.
    Success,
    /// The behaviour ran to its end and the change did not happen.
    Failure,
    /// Stopped before its end, by a person or a safety limit.
    Aborted,
    /// The robot's software or hardware failed.
    Error,
}

impl Outcome {
    pub const ALL: [Outcome; 4] = [Self::Success, Self::Failure, Self::Aborted, Self::Error];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::Success => "success",
            Self::Failure => "failure",
            Self::Aborted => "aborted",
            Self::Error => "error",
        }
    }
}

/// Why an attempt was made. Only real use says how well an action goes for the people it is
/// done for; experiments fail on purpose and tests exercise the machinery.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum Purpose {
    /// Done because someone wanted it done.
    #[default]
    Use,
    /// Part of an experiment, such as the paper's Table I protocol.
    Experiment,
    /// Checking the robot or the registry.
    Test,
}

impl Purpose {
    pub const ALL: [Purpose; 3] = [Self::Use, Self::Experiment, Self::Test];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::Use => "use",
            Self::Experiment => "experiment",
            Self::Test => "test",
        }
    }

    /// The purpose spelled as in the schema, or `None`.
    pub fn parse(text: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|purpose| purpose.as_str() == text)
    }

    pub fn is_use(&self) -> bool {
        *self == Self::Use
    }
}

/// One reading of a finger's force-torque sensor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ForceSample {
    /// Seconds since the trial's `started_at`.
    pub t: f64,
    pub finger: Finger,
    /// `[fx, fy, fz]`, newtons, on the finger, in the robot's base frame (x forward, y left, z up).
    pub force: [f64; 3],
    /// `[tx, ty, tz]`, newton-metres, about the finger's base, in the robot's base frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque: Option<[f64; 3]>,
}

/// Which finger a sample came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Finger {
    Left,
    Right,
}

/// Where the base was when the attempt started, in the map frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StartPose {
    /// Metres.
    pub x: f64,
    /// Metres.
    pub y: f64,
    /// Radians, −π..=π, counter-clockwise from x.
    pub yaw: f64,
}
