//! The shapes of the registry's own answers and request bodies that are not contract documents:
//! problems, pages, stored records, statistics, tokens, sessions, users.
//!
//! Written by hand from what the handlers send; `server/tests/openapi.rs` and the Schemathesis
//! step hold them against real answers.
//!
//! Long because it is one table, a shape per answer, read top to bottom beside the handlers;
//! the helpers above it are all it shares.

use serde_json::{Value, json};

use super::components::SCHEMAS;

fn component(name: &str) -> Value {
    json!({ "$ref": format!("{SCHEMAS}{name}") })
}

fn nullable(schema: Value) -> Value {
    json!({ "anyOf": [schema, { "type": "null" }] })
}

fn time() -> Value {
    json!({ "type": "string", "format": "date-time" })
}

fn text() -> Value {
    json!({ "type": "string" })
}

/// The request bodies that are not contract documents.
pub(super) fn shapes() -> Vec<(&'static str, Value)> {
    vec![
        (
            "retag",
            json!({
                "type": "object",
                "required": ["new_epc"],
                "properties": { "new_epc": component("tag/$defs/epc") }
            }),
        ),
        (
            "new_task",
            json!({
                "type": "object",
                "required": ["epc", "action"],
                "additionalProperties": false,
                "properties": {
                    "epc": component("tag/$defs/epc"),
                    "action": { "type": "string", "minLength": 1 },
                    "robot": nullable(component("robot/$defs/robot_id")),
                    "class": nullable(component("robot/$defs/robot_id")),
                    "note": nullable(json!({ "type": "string", "maxLength": 500 })),
                    "expires_at": {
                        "description": "When the task expires unless a robot took it: later \
                            than now and at most 30 days ahead. Left out or null: a day after \
                            it is asked for.",
                        "anyOf": [time(), { "type": "null" }]
                    }
                }
            }),
        ),
        (
            "task_finish",
            json!({
                "type": "object",
                "required": ["trial", "outcome"],
                "additionalProperties": false,
                "properties": {
                    "trial": { "type": "string", "format": "uuid" },
                    "outcome": { "enum": ["success", "failure", "aborted", "error"] }
                }
            }),
        ),
        (
            "task_decline",
            json!({
                "type": "object",
                "required": ["reason"],
                "additionalProperties": false,
                "properties": {
                    "reason": {
                        "description": "Why this robot cannot do the task: one line of plain \
                            words",
                        "type": "string",
                        "minLength": 1,
                        "maxLength": 500,
                        "pattern": "^[^\\u0000-\\u001f\\u007f-\\u009f]*[^\\s\\u0000-\\u001f\\u007f-\\u009f][^\\u0000-\\u001f\\u007f-\\u009f]*$"
                    }
                }
            }),
        ),
        (
            "verdict",
            json!({
                "description": "A merge patch of a trial: only the person's verdict may change.",
                "type": "object",
                "properties": { "confirmed": { "type": ["boolean", "null"] } }
            }),
        ),
        (
            "new_token",
            json!({
                "type": "object",
                "required": ["role", "name"],
                "additionalProperties": false,
                "properties": {
                    "role": component("role"),
                    "name": {
                        "type": "string",
                        "description": "Who holds it; for a robot token, the robot's id"
                    },
                    "expires_in_days": {
                        "type": "number", "exclusiveMinimum": 0, "maximum": 3650
                    }
                }
            }),
        ),
        (
            "login",
            json!({
                "type": "object",
                "required": ["username", "password"],
                "additionalProperties": false,
                "properties": { "username": text(), "password": text() }
            }),
        ),
        (
            "user_name",
            json!({
                "description": "Letters, digits, '.', '_' and '-', starting with a letter or \
                    digit; stored lower-case",
                "type": "string",
                "pattern": "^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$"
            }),
        ),
        (
            "password",
            json!({
                "description": "At least 8 characters, at most 256 bytes, not only spaces",
                "type": "string",
                "minLength": 8,
                "maxLength": 256
            }),
        ),
        (
            "new_user",
            json!({
                "type": "object",
                "required": ["name", "role", "password"],
                "additionalProperties": false,
                "properties": {
                    "name": component("user_name"),
                    "role": { "enum": ["admin", "caretaker"] },
                    "password": component("password")
                }
            }),
        ),
        (
            "password_change",
            json!({
                "type": "object",
                "required": ["password"],
                "additionalProperties": false,
                "properties": {
                    "password": component("password"),
                    "current_password": {
                        "type": "string",
                        "description": "Needed unless an admin changes it"
                    }
                }
            }),
        ),
    ]
}
