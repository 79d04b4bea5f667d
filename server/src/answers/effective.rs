//! The effective entry: one tag as one robot should use it (DESIGN §3), as robots read it.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::Serialize;
use serde_json::Value;

use super::contract;

/// The entry as one robot should use it: base, learned values, class and robot overrides
/// merged, with the source of every leaf.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[schemars(rename = "effective_entry", title = "Effective entry")]
pub struct EffectiveEntry {
    #[schemars(with = "contract::Epc")]
    pub epc: String,
    #[schemars(with = "contract::RobotId")]
    pub robot: String,
    /// The stored entry's revision the merge started from.
    #[schemars(range(min = 1))]
    pub revision: i64,
    /// The merged entry, overrides applied and removed.
    #[schemars(with = "contract::Tag")]
    pub entry: Value,
    /// The source of every merged leaf, by its JSON pointer: `base`, `learned`,
    /// `class:<class>` or `robot:<id>`.
    #[schemars(extend("additionalProperties" = {
        "type": "string",
        "pattern": "^(base|learned|class:.+|robot:.+)$"
    }))]
    pub provenance: BTreeMap<String, String>,
    pub unavailable_actions: Vec<UnavailableAction>,
}

/// An action of the entry that this robot cannot run, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
#[schemars(rename = "unavailable_action")]
pub struct UnavailableAction {
    pub action: String,
    /// The key in the entry's `behaviors` the action runs.
    pub behavior: String,
    /// Why, in words: the behaviour the robot lacks, or the limit a parameter exceeds.
    pub reason: String,
}
