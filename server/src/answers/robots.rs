//! Answers about robots: a robot as registered, with when it last called.

use schemars::JsonSchema;
use serde::Serialize;
use serde_json::{Map, Value, json};
use time::OffsetDateTime;

use super::{document_without, stamp};
use crate::store::robots::StoredRobot;

/// A robot as registered (`robot.schema.json`), with `last_seen`.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "stored_robot", extend("allOf" = [{ "$ref": "#/components/schemas/robot" }]))]
pub struct StoredRobotAnswer {
    /// The robot as PUT; for a robot known only from its token, its id, no class and no
    /// capabilities.
    #[serde(flatten)]
    #[schemars(skip)]
    pub document: Map<String, Value>,
    /// When it last called the registry; `null` before it ever did.
    #[serde(with = "stamp::option")]
    #[schemars(with = "Option<stamp::DateTime>")]
    pub last_seen: Option<OffsetDateTime>,
}

impl StoredRobotAnswer {
    /// `robot` with `last_seen`, as presence keeps it.
    pub fn new(robot: &StoredRobot, last_seen: Option<OffsetDateTime>) -> Self {
        let document = robot.document.clone().unwrap_or_else(|| {
            // Minted a token before an admin registered it: it shows up without a class.
            json!({ "id": robot.id, "class": null, "name": robot.id, "capabilities": [] })
        });
        Self { document: document_without(&document, &["last_seen"]), last_seen }
    }
}
