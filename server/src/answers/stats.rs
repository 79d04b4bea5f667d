//! Answers about how a tag's actions have gone: per action and robot class.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::Serialize;
use time::OffsetDateTime;

use super::{contract, stamp};

/// How a tag's actions have gone, per robot class.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "tag_stats")]
pub struct TagStats {
    #[schemars(with = "contract::Epc")]
    pub epc: String,
    /// The purposes whose trials the numbers count; always `use`.
    #[schemars(with = "Vec<contract::Purpose>")]
    pub counted: Vec<&'static str>,
    /// How many of the tag's trials of each other purpose were left out.
    #[schemars(extend("additionalProperties" = { "type": "integer", "minimum": 1 }))]
    pub not_counted: BTreeMap<String, i64>,
    pub groups: Vec<ActionStats>,
    /// The tag's size learned from every robot's confirmed reads; `null` before three. Robots
    /// get it only while the entry has no `tag_size` of its own.
    pub learned_size: Option<LearnedSizeAnswer>,
}

/// A tag's size learned from the robots' measurements of it.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "learned_size")]
pub struct LearnedSizeAnswer {
    /// Metres, across.
    #[schemars(range(min = 0.01, max = 1))]
    pub width: f64,
    /// Metres, at right angles to the width along the surface.
    #[schemars(range(min = 0.01, max = 1))]
    pub height: f64,
    /// The confirmed trials it was learned from.
    #[schemars(range(min = 3))]
    pub trials: i64,
}

/// One action as done by one robot class.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "action_stats")]
pub struct ActionStats {
    pub action: String,
    /// `null` for robots registered without a class.
    pub robot_class: Option<String>,
    #[schemars(range(min = 0))]
    pub attempts: i64,
    /// Trials the robot's own detector called a success.
    #[schemars(range(min = 0))]
    pub detected_successes: i64,
    /// Trials the person gave a verdict on.
    #[schemars(range(min = 0))]
    pub confirmed: i64,
    /// Trials the person called a success.
    #[schemars(range(min = 0))]
    pub confirmed_successes: i64,
    /// Share of verdicts that agree with the detector; `null` before any verdict.
    #[schemars(range(min = 0, max = 1))]
    pub agreement: Option<f64>,
    /// Successes (the person's verdict where given, else the detector's) over attempts.
    #[schemars(range(min = 0, max = 1))]
    pub success_rate: Option<f64>,
    /// The lab's rule over the most recent attempts: at least 20, at least 90 % successful.
    pub reliable: bool,
    #[serde(with = "stamp::option")]
    #[schemars(with = "Option<stamp::DateTime>")]
    pub last_attempt: Option<OffsetDateTime>,
    /// Learned values by the JSON pointer of the parameter.
    pub learned: BTreeMap<String, LearnedValue>,
}

/// A parameter's value learned from trials.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "learned_value")]
pub struct LearnedValue {
    pub value: f64,
    /// The trials it was learned from.
    #[schemars(range(min = 0))]
    pub trials: i64,
}
