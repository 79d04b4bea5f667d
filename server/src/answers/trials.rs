//! Answers about trials: a trial as stored, as the API and the export give it.

use schemars::JsonSchema;
use serde::Serialize;
use serde_json::{Map, Value};
use time::OffsetDateTime;

use super::{contract, document_without, stamp};
use crate::store::trials::{TrialRow, picture_path};

/// The fields the registry answers itself, whatever the robot sent.
const REGISTRY_FIELDS: [&str; 5] = ["confirmed", "purpose", "received_at", "seq", "picture"];

/// A trial as submitted, with the verdict as it is now, its purpose spelled out also where
/// real use went without saying, and what the registry adds.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "stored_trial", extend("allOf" = [{ "$ref": "#/components/schemas/trial" }]))]
pub struct StoredTrialAnswer {
    /// The trial as the robot submitted it (`trial.schema.json`).
    #[serde(flatten)]
    #[schemars(skip)]
    pub submitted: Map<String, Value>,
    /// The person's verdict; `null` until someone gives one.
    pub confirmed: Option<bool>,
    #[schemars(with = "contract::Purpose")]
    pub purpose: String,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub received_at: OffsetDateTime,
    /// The order the registry received trials in.
    pub seq: i64,
    /// Where the trial's picture is read; `null` when it has none.
    pub picture: Option<String>,
}

impl From<&TrialRow> for StoredTrialAnswer {
    fn from(row: &TrialRow) -> Self {
        let submitted: Value = serde_json::from_str(&row.body).unwrap_or(Value::Null);
        Self {
            submitted: document_without(&submitted, &REGISTRY_FIELDS),
            confirmed: row.confirmed,
            purpose: row.purpose.clone(),
            received_at: row.received_at,
            seq: row.seq,
            picture: row.has_picture.then(|| picture_path(&row.id)),
        }
    }
}
