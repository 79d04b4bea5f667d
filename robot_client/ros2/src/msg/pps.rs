//! `pps_msgs`: the registry's side of the node, as `pps_msgs/msg/*.msg` declares it.

use serde::{Deserialize, Serialize};

use super::builtin::Time;
use super::ros_message;

/// `pps_msgs/TagRead`: one reply of one tag to one finger antenna.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TagRead {
    pub epc: String,
    pub rssi_dbm: f64,
    pub antenna: u8,
}
ros_message!(TagRead, "pps_msgs", "TagRead");

/// `pps_msgs/TagReads`: one inventory round of the finger readers.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TagReads {
    pub stamp: Time,
    pub reads: Vec<TagRead>,
}
ros_message!(TagReads, "pps_msgs", "TagReads");

/// `pps_msgs/TagEntry`: the robot's effective entry for the tag the round chose.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TagEntry {
    pub stamp: Time,
    /// The chosen (strongest) tag; empty when nothing answered.
    pub epc: String,
    pub ambiguous: bool,
    /// The entry's revision, e.g. `r3`; empty when not found.
    pub revision: String,
    /// The effective entry document exactly as the registry returns it.
    pub entry_json: String,
    pub unavailable_actions: Vec<String>,
    /// Empty on success; otherwise a sentence (unknown tag, registry unreachable).
    pub error: String,
}
ros_message!(TagEntry, "pps_msgs", "TagEntry");

/// `pps_msgs/Trial`: a trial document to record.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Trial {
    pub trial_json: String,
}
ros_message!(Trial, "pps_msgs", "Trial");
