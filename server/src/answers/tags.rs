//! Answers about tags: a stored entry with its read-only fields, one change in its history, and
//! the verdict of a validation.

use schemars::JsonSchema;
use serde::Serialize;
use serde_json::{Map, Value};
use time::OffsetDateTime;

use super::{contract, document_without, stamp};
use crate::store::tags::{Revision, StoredTag};

/// The fields the registry adds to a stored entry on GET (and ignores on PUT).
const READ_ONLY: [&str; 5] = ["epc_uri", "revision", "updated_at", "updated_by", "archived"];

/// A tag entry as stored, with the read-only fields the registry adds.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "stored_tag", extend("allOf" = [{ "$ref": "#/components/schemas/tag" }]))]
pub struct StoredTagAnswer {
    /// The entry as PUT (`tag.schema.json`).
    #[serde(flatten)]
    #[schemars(skip)]
    pub entry: Map<String, Value>,
    /// The GS1 pure-identity URI, when the EPC decodes into one.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(with = "String")]
    pub epc_uri: Option<String>,
    /// Counts the entry's changes from 1; its ETag is `"r<revision>"`.
    #[schemars(range(min = 1))]
    pub revision: i64,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub updated_at: OffsetDateTime,
    /// Who made the last change.
    pub updated_by: String,
    pub archived: bool,
}

impl From<&StoredTag> for StoredTagAnswer {
    fn from(tag: &StoredTag) -> Self {
        Self {
            entry: document_without(&tag.entry, &READ_ONLY),
            epc_uri: tag.epc.pure_identity_uri(),
            revision: tag.revision,
            updated_at: tag.updated_at,
            updated_by: tag.updated_by.clone(),
            archived: tag.archived,
        }
    }
}

/// What one change did to a tag.
#[derive(Debug, Clone, Copy, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
#[schemars(rename = "tag_change")]
pub enum Change {
    Create,
    Replace,
    Archive,
    Restore,
    Retag,
}

/// One change in a tag's history: who, when, and the full entry after it.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "tag_revision")]
pub struct TagRevisionAnswer {
    #[schemars(range(min = 1))]
    pub revision: i64,
    #[schemars(with = "Change")]
    pub change: String,
    pub archived: bool,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub changed_at: OffsetDateTime,
    pub changed_by: String,
    #[schemars(with = "contract::Tag")]
    pub entry: Value,
}

impl From<Revision> for TagRevisionAnswer {
    fn from(revision: Revision) -> Self {
        Self {
            revision: revision.revision,
            changed_at: revision.changed_at,
            change: revision.change,
            archived: revision.archived,
            changed_by: revision.changed_by,
            entry: revision.entry,
        }
    }
}

/// The answer to a valid entry (an invalid one is a 422 problem listing every error).
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "validation_result")]
pub struct ValidationResult {
    #[schemars(extend("const" = true))]
    valid: bool,
    #[schemars(length(max = 0))]
    errors: Vec<Value>,
}

impl ValidationResult {
    pub const VALID: Self = Self { valid: true, errors: Vec::new() };
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    #[test]
    fn a_stored_tag_says_its_own_read_only_fields_once() {
        // An entry PUT back after a GET carries the read-only fields of that older read.
        let entry = json!({
            "epc": "E20034120000000000001001",
            "actions": {},
            "revision": 1,
            "updated_by": "someone else",
            "archived": true
        });
        let tag = StoredTag {
            epc: pps_schema::Epc::parse("E20034120000000000001001").unwrap(),
            entry,
            revision: 4,
            archived: false,
            updated_at: time::macros::datetime!(2026-03-04 05:06:07.089 UTC),
            updated_by: "nurse".into(),
        };
        let text = serde_json::to_string(&StoredTagAnswer::from(&tag)).unwrap();
        assert_eq!(text.matches("\"revision\"").count(), 1, "{text}");
        let answer: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(
            answer,
            json!({
                "epc": "E20034120000000000001001",
                "actions": {},
                "revision": 4,
                "updated_at": "2026-03-04T05:06:07.089Z",
                "updated_by": "nurse",
                "archived": false
            })
        );
    }
}
