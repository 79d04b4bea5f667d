//! The shapes of the registry's own answers and request bodies that are not contract documents:
//! problems, pages, stored records, statistics, tokens, sessions, users.
//!
//! Written by hand from what the handlers send; `server/tests/suite/openapi.rs` and the Schemathesis
//! step hold them against real answers.
//!
//! Long because it is one table, a shape per answer, read top to bottom beside the handlers;
//! the helpers above it are all it shares.

use serde_json::{Value, json};

use super::components::SCHEMAS;

fn component(name: &str) -> Value {
    json!({ "$ref": format!("{SCHEMAS}{name}") })
}

/// A schema with `required` added to a contract schema, for answers that always carry fields
/// that are optional on input.
fn always_with(base: &str, required: &[&str]) -> Value {
    json!({ "allOf": [component(base), { "required": required }] })
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

fn object(required: &[&str], properties: Value) -> Value {
    json!({ "type": "object", "required": required, "properties": properties })
}

/// The answers of the registry that are not contract documents.
pub(super) fn shapes() -> Vec<(&'static str, Value)> {
    vec![
        (
            "problem",
            json!({
                "title": "Problem (RFC 9457)",
                "description": "Every error: what went wrong, in words a person can act on; \
                    a validation error lists every problem in `errors`.",
                "type": "object",
                "required": ["type", "title", "status", "detail"],
                "properties": {
                    "type": { "type": "string", "format": "uri" },
                    "title": text(),
                    "status": { "type": "integer", "minimum": 400, "maximum": 599 },
                    "detail": { "type": "string", "minLength": 1 },
                    "errors": { "type": "array", "items": component("field_error") }
                }
            }),
        ),
        (
            "field_error",
            object(
                &["pointer", "message"],
                json!({
                    "pointer": {
                        "type": "string",
                        "description": "RFC 6901 JSON pointer to the field (\"\" for the whole \
                            document); for a missing field, where it belongs"
                    },
                    "message": { "type": "string", "minLength": 1 }
                }),
            ),
        ),
        (
            "stored_tag",
            always_with("tag", &["epc", "revision", "updated_at", "updated_by", "archived"]),
        ),
        (
            "tag_revision",
            object(
                &["revision", "change", "archived", "changed_at", "changed_by", "entry"],
                json!({
                    "revision": { "type": "integer", "minimum": 1 },
                    "change": { "enum": ["create", "replace", "archive", "restore", "retag"] },
                    "archived": { "type": "boolean" },
                    "changed_at": time(),
                    "changed_by": text(),
                    "entry": component("tag")
                }),
            ),
        ),
        (
            "validation_result",
            object(
                &["valid", "errors"],
                json!({
                    "valid": { "const": true },
                    "errors": { "type": "array", "maxItems": 0 }
                }),
            ),
        ),
        (
            "retag",
            json!({
                "type": "object",
                "required": ["new_epc"],
                "properties": { "new_epc": component("tag/$defs/epc") }
            }),
        ),
        (
            "tag_stats",
            object(
                &["epc", "counted", "not_counted", "groups"],
                json!({
                    "epc": component("tag/$defs/epc"),
                    "counted": {
                        "description": "The purposes whose trials the numbers count; always `use`.",
                        "type": "array",
                        "items": component("trial/properties/purpose")
                    },
                    "not_counted": {
                        "description": "How many of the tag's trials of each other purpose were left out.",
                        "type": "object",
                        "additionalProperties": { "type": "integer", "minimum": 1 }
                    },
                    "groups": { "type": "array", "items": component("action_stats") }
                }),
            ),
        ),
        (
            "action_stats",
            json!({
                "description": "One action as done by one robot class.",
                "type": "object",
                "required": ["action", "robot_class", "attempts", "detected_successes",
                    "confirmed", "confirmed_successes", "agreement", "success_rate",
                    "reliable", "last_attempt", "learned"],
                "properties": {
                    "action": text(),
                    "robot_class": nullable(text()),
                    "attempts": { "type": "integer", "minimum": 0 },
                    "detected_successes": { "type": "integer", "minimum": 0 },
                    "confirmed": { "type": "integer", "minimum": 0 },
                    "confirmed_successes": { "type": "integer", "minimum": 0 },
                    "agreement": nullable(json!({ "type": "number", "minimum": 0, "maximum": 1 })),
                    "success_rate":
                        nullable(json!({ "type": "number", "minimum": 0, "maximum": 1 })),
                    "reliable": { "type": "boolean" },
                    "last_attempt": nullable(time()),
                    "learned": {
                        "description": "Learned values by the JSON pointer of the parameter.",
                        "type": "object",
                        "additionalProperties": object(&["value", "trials"], json!({
                            "trials": { "type": "integer", "minimum": 0 }
                        }))
                    }
                }
            }),
        ),
        ("stored_robot", always_with("robot", &["last_seen"])),
        (
            "effective_entry",
            json!({
                "title": "Effective entry",
                "description": "The entry as one robot should use it: base, learned values, \
                    class and robot overrides merged, with the source of every leaf.",
                "type": "object",
                "required": ["epc", "robot", "revision", "entry", "provenance",
                    "unavailable_actions"],
                "properties": {
                    "epc": component("tag/$defs/epc"),
                    "robot": component("robot/$defs/robot_id"),
                    "revision": { "type": "integer", "minimum": 1 },
                    "entry": component("tag"),
                    "provenance": {
                        "type": "object",
                        "additionalProperties": {
                            "type": "string",
                            "pattern": "^(base|learned|class:.+|robot:.+)$"
                        }
                    },
                    "unavailable_actions": {
                        "type": "array",
                        "items": object(&["action", "behavior", "reason"], json!({
                            "action": text(), "behavior": text(), "reason": text()
                        }))
                    }
                }
            }),
        ),
        (
            "inbox_item",
            object(
                &["epc", "robots", "first_seen", "last_seen", "count"],
                json!({
                    "epc": component("tag/$defs/epc"),
                    "epc_uri": text(),
                    "robots": { "type": "array", "items": component("robot/$defs/robot_id") },
                    "first_seen": time(),
                    "last_seen": time(),
                    "count": { "type": "integer", "minimum": 1 }
                }),
            ),
        ),
        (
            "stored_trial",
            always_with("trial", &["confirmed", "purpose", "received_at", "seq", "picture"]),
        ),
        (
            "task",
            object(
                &[
                    "id",
                    "epc",
                    "action",
                    "robot",
                    "class",
                    "note",
                    "state",
                    "created_by",
                    "created_at",
                    "claimed_by",
                    "lease_until",
                    "attempts",
                    "holders",
                    "trial",
                    "reason",
                    "updated_at",
                    "declined",
                    "waiting_for",
                    "stuck",
                    "expires_at",
                    "expired",
                ],
                json!({
                    "id": { "type": "string", "format": "uuid" },
                    "epc": component("tag/$defs/epc"),
                    "action": text(),
                    "robot": nullable(component("robot/$defs/robot_id")),
                    "class": nullable(component("robot/$defs/robot_id")),
                    "note": nullable(text()),
                    "state": { "enum": pps_schema::TaskState::NAMES },
                    "created_by": text(),
                    "created_at": time(),
                    "claimed_by": {
                        "description": "The holder; once ended, the robot that ended it",
                        "anyOf": [component("robot/$defs/robot_id"), { "type": "null" }]
                    },
                    "lease_until": nullable(time()),
                    "attempts": {
                        "description": "How many times a robot claimed it",
                        "type": "integer", "minimum": 0
                    },
                    "holders": { "type": "array", "items": component("robot/$defs/robot_id") },
                    "trial": nullable(json!({ "type": "string", "format": "uuid" })),
                    "reason": nullable(text()),
                    "updated_at": time(),
                    "declined": {
                        "description": "Every robot that declined it and why, in order; it is \
                            never offered to them again",
                        "type": "array",
                        "items": object(&["robot", "reason", "at"], json!({
                            "robot": component("robot/$defs/robot_id"),
                            "reason": text(),
                            "at": time()
                        }))
                    },
                    "waiting_for": {
                        "description": "While queued: the robots online (seen in the last \
                            minute) that may take it now",
                        "type": "array",
                        "items": component("robot/$defs/robot_id")
                    },
                    "stuck": {
                        "description": "While queued and no robot online may take it: why, in \
                            words (who declined and why, who could but is offline, or that no \
                            robot can). It stays queued until a robot can take it.",
                        "anyOf": [text(), { "type": "null" }]
                    },
                    "expires_at": {
                        "description": "When it expires unless a robot took it (or, holding \
                            it, finished it); null for never (tasks asked for before tasks \
                            could expire)",
                        "anyOf": [time(), { "type": "null" }]
                    },
                    "expired": {
                        "description": "Whether it ended because it expired: it is then \
                            `cancelled`, and `reason` says so in words",
                        "type": "boolean"
                    }
                }),
            ),
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
        ("role", json!({ "enum": ["admin", "caretaker", "robot"] })),
        (
            "token_record",
            object(
                &["id", "name", "role", "robot_id", "created_at", "expires_at", "revoked_at"],
                json!({
                    "id": text(),
                    "name": text(),
                    "role": component("role"),
                    "robot_id": nullable(component("robot/$defs/robot_id")),
                    "created_at": time(),
                    "expires_at": nullable(time()),
                    "revoked_at": nullable(time())
                }),
            ),
        ),
        (
            "minted_token",
            json!({
                "allOf": [
                    component("token_record"),
                    object(&["token"], json!({
                        "token": {
                            "type": "string",
                            "description": "The secret, shown only in this answer"
                        }
                    }))
                ]
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
            "revoked_token",
            object(&["id", "revoked"], json!({ "id": text(), "revoked": { "const": true } })),
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
            "session",
            json!({
                "description": "Who the credential belongs to; for a browser session also its \
                    expiry and the anti-forgery token unsafe requests must send in X-CSRF-Token.",
                "type": "object",
                "required": ["name", "role", "credential"],
                "properties": {
                    "name": text(),
                    "role": component("role"),
                    "credential": { "enum": ["session", "token"] },
                    "expires_at": time(),
                    "csrf_token": text(),
                    "robot": nullable(text())
                }
            }),
        ),
        (
            "user",
            object(
                &["name", "role", "created_at", "password_changed_at"],
                json!({
                    "name": text(),
                    "role": { "enum": ["admin", "caretaker"] },
                    "created_at": time(),
                    "password_changed_at": time()
                }),
            ),
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
        ("health", object(&["status"], json!({ "status": { "const": "ok" } }))),
        (
            "home_assistant_bridge",
            object(
                &["bridge", "broker", "prefix"],
                json!({
                    "bridge": { "enum": ["off", "standby", "connecting", "connected"] },
                    "broker": {
                        "type": ["string", "null"],
                        "description": "The broker's URL without its password; null when off"
                    },
                    "prefix": {
                        "type": ["string", "null"],
                        "description": "Home Assistant's discovery prefix; null when off"
                    }
                }),
            ),
        ),
        (
            "json_schema",
            json!({
                "description": "A JSON Schema (2020-12) document of the contract, as published.",
                "type": "object",
                "required": ["$schema", "$id"]
            }),
        ),
        (
            "openapi",
            json!({
                "description": "This document.",
                "type": "object",
                "required": ["openapi", "paths"]
            }),
        ),
    ]
}
