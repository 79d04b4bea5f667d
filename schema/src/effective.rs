//! The effective entry: what one robot reads for one tag, with every override merged in.

use std::collections::BTreeMap;
use std::fmt;

use serde::{Deserialize, Serialize};

use crate::entry::TagEntry;
use crate::epc::Epc;
use crate::robot_id::RobotId;

/// The entry as `robot` should use it: base ← learned ← class override ← robot override.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EffectiveEntry {
    pub epc: Epc,
    pub robot: RobotId,
    /// The revision of the stored entry this was merged from.
    pub revision: u64,
    pub entry: TagEntry,
    /// JSON pointer (RFC 6901) of each merged leaf in `entry` → where its value came from.
    pub provenance: BTreeMap<String, Provenance>,
    #[serde(default)]
    pub unavailable_actions: Vec<UnavailableAction>,
}

/// Where a merged value came from. Written as `base`, `learned`, `class:<class>` or
/// `robot:<robot id>`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(into = "String", try_from = "String")]
pub enum Provenance {
    /// The entry as stored.
    Base,
    /// Learned from trials: this robot class's, or every robot's for a tag's size.
    Learned,
    /// The override for the robot's class.
    Class(RobotId),
    /// The override for the robot itself.
    Robot(RobotId),
}

impl fmt::Display for Provenance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Base => f.write_str("base"),
            Self::Learned => f.write_str("learned"),
            Self::Class(class) => write!(f, "class:{class}"),
            Self::Robot(robot) => write!(f, "robot:{robot}"),
        }
    }
}

/// A string that is not a [`Provenance`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?} is not a provenance: expected base, learned, class:<class> or robot:<robot id>")]
pub struct ProvenanceError(String);

impl std::str::FromStr for Provenance {
    type Err = ProvenanceError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let invalid = || ProvenanceError(s.to_owned());
        match s.split_once(':') {
            None if s == "base" => Ok(Self::Base),
            None if s == "learned" => Ok(Self::Learned),
            Some(("class", id)) => RobotId::parse(id).map(Self::Class).map_err(|_| invalid()),
            Some(("robot", id)) => RobotId::parse(id).map(Self::Robot).map_err(|_| invalid()),
            _ => Err(invalid()),
        }
    }
}

impl From<Provenance> for String {
    fn from(provenance: Provenance) -> Self {
        provenance.to_string()
    }
}

impl TryFrom<String> for Provenance {
    type Error = ProvenanceError;
    fn try_from(value: String) -> Result<Self, Self::Error> {
        value.parse()
    }
}

/// An action of the entry that this robot must not attempt, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct UnavailableAction {
    pub action: String,
    /// The key in `behaviors` the action names.
    pub behavior: String,
    /// A sentence for people, e.g. "EL-E cannot run pull_lamp".
    pub reason: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn provenance_reads_and_writes_its_four_forms() {
        let robot = RobotId::parse("el-e-1").unwrap();
        let class = RobotId::parse("el-e").unwrap();
        for (text, provenance) in [
            ("base", Provenance::Base),
            ("learned", Provenance::Learned),
            ("class:el-e", Provenance::Class(class)),
            ("robot:el-e-1", Provenance::Robot(robot)),
        ] {
            assert_eq!(text.parse::<Provenance>(), Ok(provenance.clone()));
            assert_eq!(serde_json::to_value(&provenance).unwrap(), serde_json::json!(text));
        }
        for bad in ["", "Base", "class:", "robot:EL-E", "user:ann", "base:x"] {
            assert!(bad.parse::<Provenance>().is_err(), "{bad}");
        }
    }
}
