//! Links between tags: the paper's "tags that reference one another".

use serde::{Deserialize, Serialize};

use crate::epc::Epc;

/// A relation from the entry holding it to another tag.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Link {
    pub rel: LinkRel,
    /// The other tag; never the entry's own EPC.
    pub target: Epc,
    /// A note for people, e.g. `ceiling light`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// How the entry relates to the link's target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LinkRel {
    /// A switch controls a ceiling light.
    Controls,
    ControlledBy,
    /// A drawer is part of a cabinet.
    PartOf,
    HasPart,
    Near,
}
