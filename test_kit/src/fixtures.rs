//! The content tests set the scene with in a registry process: robots, trials, tags.

use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

use crate::api::ALL;
pub use crate::api::{ADA_SWITCH, DRAWER};
use crate::process::Registry;

/// Registers `id` of `class` as an admin and mints its token.
pub async fn robot(registry: &Registry, id: &str, class: &str) -> String {
    let record = json!({
        "id": id, "class": class, "name": id.to_uppercase(),
        "capabilities": ALL,
        "limits": { "max_force": 15.0 }
    });
    let path = format!("/api/v1/robots/{id}");
    let (status, body) =
        registry.call(Method::PUT, &path, &registry.admin_token, Some(&record), &[]).await;
    assert!(status.is_success(), "PUT {path}: {status} {body}");
    registry.token("robot", id)
}

/// A trial of `robot` switching the ADA switch on, under a fresh id.
pub fn switch_trial(robot: &str) -> Value {
    json!({
        "id": uuid::Uuid::new_v4(), "epc": ADA_SWITCH, "robot": robot, "action": "on",
        "behavior": "push_top", "started_at": "2026-11-22T10:00:00Z",
        "finished_at": "2026-11-22T10:00:30Z", "outcome": "success", "confirmed": null,
        "detector": { "brightness_change": 0.3 }, "forces": [], "measurements": {}
    })
}

/// A successful pull back of the drawer by `robot` that measured `displacement` (any JSON).
pub fn pull_trial(robot: &str, displacement: Value) -> Value {
    json!({
        "id": uuid::Uuid::new_v4(), "epc": DRAWER, "robot": robot, "action": "open",
        "behavior": "pull_open", "started_at": "2026-11-22T10:00:00Z",
        "finished_at": "2026-11-22T10:00:30Z", "outcome": "success", "confirmed": null,
        "detector": { "displacement_m": 0.3 }, "forces": [],
        "measurements": { "displacement": displacement }
    })
}

/// PUTs a trial as `token`; the status and body.
pub async fn put_trial(registry: &Registry, token: &str, trial: &Value) -> (StatusCode, Value) {
    let path = format!("/api/v1/trials/{}", trial["id"].as_str().expect("a trial id"));
    registry.call(Method::PUT, &path, token, Some(trial), &[]).await
}

/// Registers a new tag at `epc` named `name`, a copy of the tag at `from` (so it is a device
/// no simulated room has).
pub async fn copy_tag(registry: &Registry, from: &str, epc: &str, name: &str) {
    let mut entry: Value = registry.get(&format!("/api/v1/tags/{from}")).await;
    for key in ["epc_uri", "revision", "updated_at", "updated_by", "archived"] {
        entry.as_object_mut().unwrap().remove(key);
    }
    entry["epc"] = epc.into();
    entry["properties"]["name"] = name.into();
    let path = format!("/api/v1/tags/{epc}");
    let (status, body) = registry
        .call(Method::PUT, &path, &registry.admin_token, Some(&entry), &[("if-none-match", "*")])
        .await;
    assert_eq!(status, StatusCode::CREATED, "PUT {path}: {body}");
}
