//! Answers about trials: a trial as stored, as the API and the export give it.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::Serialize;
use serde_json::value::RawValue;
use time::OffsetDateTime;

use super::{contract, stamp};
use crate::store::trials::{TrialRow, picture_path};

/// The fields the registry answers itself, whatever the robot sent.
const REGISTRY_FIELDS: [&str; 5] = ["confirmed", "purpose", "received_at", "seq", "picture"];

/// A trial as submitted, with the verdict as it is now, its purpose spelled out also where
/// real use went without saying, and what the registry adds.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "stored_trial", extend("allOf" = [{ "$ref": "#/components/schemas/trial" }]))]
pub struct StoredTrialAnswer {
    /// The trial as the robot submitted it (`trial.schema.json`), each value as stored: a
    /// page of trials holds many thousands of force samples, and parsing them into numbers
    /// only to print them again was most of what a page cost.
    #[serde(flatten)]
    #[schemars(skip)]
    pub submitted: BTreeMap<String, Box<RawValue>>,
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
        // The store holds what the registry accepted, an object; anything else shows as none.
        let mut submitted: BTreeMap<String, Box<RawValue>> =
            serde_json::from_str(&row.body).unwrap_or_default();
        submitted.retain(|key, _| !REGISTRY_FIELDS.contains(&key.as_str()));
        Self {
            submitted,
            confirmed: row.confirmed,
            purpose: row.purpose.clone(),
            received_at: row.received_at,
            seq: row.seq,
            picture: row.has_picture.then(|| picture_path(&row.id)),
        }
    }
}

#[cfg(test)]
mod tests {
    use pps_schema::{Epc, RobotId};
    use serde_json::{Value, json};
    use uuid::Uuid;

    use super::*;

    fn row(body: &str, confirmed: Option<bool>, has_picture: bool) -> TrialRow {
        TrialRow {
            seq: 42,
            id: Uuid::parse_str("0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10").unwrap(),
            epc: Epc::parse("355AB1C60000002000000001").unwrap(),
            robot: RobotId::parse("el-e-1").unwrap(),
            robot_class: Some("el-e".into()),
            action: "on".into(),
            outcome: "success".into(),
            confirmed,
            purpose: "experiment".into(),
            received_at: time::macros::datetime!(2026-11-22 10:00:31 UTC),
            body: body.into(),
            has_picture,
        }
    }

    #[test]
    fn stored_values_are_copied_as_written_and_the_registrys_fields_replace_the_robots() {
        let body = r#"{"id":"0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10","outcome":"success",
            "confirmed":false,"purpose":"test","seq":7,"notes":"a \"quoted\" \u00e9\t",
            "forces":[{"t":0.1,"finger":"left","force":[1e-7,-2.5,1.2345678901234567]}]}"#;
        let text =
            serde_json::to_string(&StoredTrialAnswer::from(&row(body, Some(true), true))).unwrap();
        assert!(text.contains("[1e-7,-2.5,1.2345678901234567]"), "{text}");
        assert!(text.contains(r#""a \"quoted\" \u00e9\t""#), "{text}");
        let answer: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(
            answer,
            json!({
                "id": "0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10", "outcome": "success",
                "notes": "a \"quoted\" é\t",
                "forces": [{ "t": 0.1, "finger": "left", "force": [1e-7, -2.5, 1.2345678901234567] }],
                "confirmed": true, "purpose": "experiment",
                "received_at": "2026-11-22T10:00:31.000Z", "seq": 42,
                "picture": "/api/v1/trials/0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10/picture"
            })
        );
    }

    #[test]
    fn a_body_that_is_not_an_object_answers_with_the_registrys_fields_alone() {
        let answer = serde_json::to_value(StoredTrialAnswer::from(&row("[1,2]", None, false)));
        let answer = answer.unwrap();
        let keys: Vec<&str> = answer.as_object().unwrap().keys().map(String::as_str).collect();
        assert_eq!(keys.len(), 5, "{answer}");
        assert!(keys.iter().all(|key| REGISTRY_FIELDS.contains(key)), "{answer}");
    }
}
