//! The tag entry: the paper's Fig. 4 made explicit.
//!
//! These types read and write entries that `tag.schema.json` accepts; they do not validate
//! (bounds, cross-references): run [`crate::validate_tag`] on the JSON first.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::behavior::BehaviorSpec;
use crate::epc::Epc;
use crate::link::Link;

/// One tag entry, as PUT by a caretaker and stored by the registry (read-only fields aside).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TagEntry {
    pub epc: Epc,
    pub properties: Properties,
    /// User-facing action name (`on`, `open`) → key in [`TagEntry::behaviors`].
    pub actions: BTreeMap<String, String>,
    /// Key → the behaviour that performs an action and its parameters.
    pub behaviors: BTreeMap<String, BehaviorSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub links: Vec<Link>,
}

impl TagEntry {
    /// The behaviour that performs `action`, with its key, if both exist.
    pub fn behavior_for(&self, action: &str) -> Option<(&str, &BehaviorSpec)> {
        let key = self.actions.get(action)?;
        self.behaviors.get_key_value(key).map(|(key, spec)| (key.as_str(), spec))
    }
}

/// What the thing is, independent of any action. Known keys are typed; any other key is kept
/// in [`Properties::other`] because the database grows bottom-up.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Properties {
    /// The class of object: `ada light switch`, `light switch`, `lamp`, `drawer`, `trash can`.
    #[serde(rename = "type", default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    /// A name unique to this object, e.g. `A D A light switch 1`.
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pps_tag: Option<PpsTagMaterial>,
    /// The state change that shows an action worked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub change: Option<StateChange>,
    /// Where to look for the change.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<LookDirection>,
    /// Height of the tag's centre above the floor, metres (0..=2.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Whether the tag lies on the surface behind it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub on_plane: Option<bool>,
    /// The red tag's size as it is stuck on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tag_size: Option<TagSize>,
    /// How far the switch moves when operated, metres (0..=0.15).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub switch_travel: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub location: Option<Location>,
    /// Robot class or robot id → properties for that robot.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub robots: BTreeMap<String, RobotProperties>,
    /// Every other key, kept as written.
    #[serde(flatten)]
    pub other: Map<String, Value>,
}

impl Properties {
    /// The tag's colour as one robot's camera sees it, in an effective entry (where the registry
    /// has merged that robot's `robots` overrides into the properties); `None` when the entry has
    /// none or it is malformed.
    pub fn color_segmentation(&self) -> Option<ColorSegmentation> {
        self.other.get("color_segmentation").and_then(|v| ColorSegmentation::deserialize(v).ok())
    }

    /// The colour the registry learned this tag to have in this robot class's camera, from the
    /// confirmed reads of it; in an effective entry only.
    pub fn learned_color(&self) -> Option<LearnedColor> {
        self.other.get(LEARNED_COLOR).and_then(|v| LearnedColor::deserialize(v).ok())
    }

    /// The colour the registry learned this household's tags to have in this robot class's
    /// camera, from the confirmed reads of all of them; in an effective entry only.
    pub fn household_color(&self) -> Option<LearnedColor> {
        self.other.get(HOUSEHOLD_COLOR).and_then(|v| LearnedColor::deserialize(v).ok())
    }
}

/// The compliant, high-friction material of a PPS-tag (paper §III-A).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PpsTagMaterial {
    Dycem,
    FoamTube,
    Towel,
}

/// The state change a success detector looks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StateChange {
    /// The room (or the lamp in front) gets brighter or darker.
    OverallBrightness,
    /// The thing moved (a drawer opened or closed).
    Location,
    /// The robot no longer holds the object it carried.
    HeldObject,
}

/// Where the robot looks to observe the change, relative to itself facing the tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LookDirection {
    Up,
    Down,
    Forward,
    Backward,
    Left,
    Right,
}

/// A tag's width and height as it is stuck on, metres (each 0.01..=1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TagSize {
    pub width: f64,
    pub height: f64,
}

impl TagSize {
    /// How far the tag reaches from its middle: half its diagonal, metres.
    pub fn reach(&self) -> f64 {
        self.width.hypot(self.height) / 2.0
    }
}

/// Where the thing is in the home.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Location {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub room: Option<String>,
    #[serde(flatten)]
    pub other: Map<String, Value>,
}

/// Properties specific to one robot class or robot.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RobotProperties {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color_segmentation: Option<ColorSegmentation>,
    #[serde(flatten)]
    pub other: Map<String, Value>,
}

/// Where an effective entry's properties carry the tag's learned colour.
pub const LEARNED_COLOR: &str = "learned_color_segmentation";
/// Where an effective entry's properties carry the household's learned colour.
pub const HOUSEHOLD_COLOR: &str = "household_color_segmentation";

/// A colour model learned from confirmed reads: thresholds, and how many reads they rest on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LearnedColor {
    #[serde(flatten)]
    pub segmentation: ColorSegmentation,
    /// The confirmed reads (trials) the model was learned from.
    pub trials: u64,
}

/// HSV thresholds that segment a PPS-tag in one robot's camera (paper §III-B).
///
/// Hue is in degrees and may wrap around 0 (`[340, 20]` is red); saturation and value are 0..=1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ColorSegmentation {
    pub hue_deg: [f64; 2],
    pub saturation: [f64; 2],
    pub value: [f64; 2],
}

impl Default for ColorSegmentation {
    /// The red of the paper's tags under a camera flash.
    fn default() -> Self {
        Self { hue_deg: [340.0, 20.0], saturation: [0.6, 1.0], value: [0.15, 1.0] }
    }
}
