//! What tests send and expect of the API: valid bodies to start from, problem answers, and
//! the seeded tags' EPCs.

use reqwest::{Response, StatusCode};
use serde_json::Value;

use crate::in_process::TestServer;

/// The seeded ADA light switch.
pub const ADA_SWITCH: &str = "355AB1C60000002000000001";
/// The seeded flip light switch.
pub const FLIP_SWITCH: &str = "355AB1C60000001000000001";
/// The seeded lamp.
pub const LAMP: &str = "355AB1C60000003000000001";
/// The seeded drawer.
pub const DRAWER: &str = "355AB1C60000004000000001";

/// Every behaviour a robot of the paper can run.
pub const ALL: &[&str] = &["light_switch", "pull_back", "push", "pull_lamp", "drop"];

/// A fresh trial id, as a robot chooses one.
pub fn uuid() -> String {
    uuid::Uuid::new_v4().to_string()
}

/// Reads a problem+json answer, checking its media type and status field.
pub async fn problem(response: Response, status: StatusCode) -> Value {
    assert_eq!(response.status(), status);
    let media = response.headers()["content-type"].to_str().unwrap().to_owned();
    assert_eq!(media, "application/problem+json");
    let body: Value = response.json().await.unwrap();
    assert_eq!(body["status"], status.as_u16());
    assert!(body["detail"].as_str().is_some_and(|d| !d.is_empty()), "{body}");
    body
}

/// The JSON pointers a validation problem lists.
pub fn pointers(problem: &Value) -> Vec<String> {
    problem["errors"]
        .as_array()
        .map(|errors| errors.iter().map(|e| e["pointer"].as_str().unwrap().to_owned()).collect())
        .unwrap_or_default()
}

/// A new valid entry for `epc`, based on the seeded ADA switch.
pub fn new_entry(epc: &str, name: &str) -> Value {
    let mut entry: Value =
        serde_json::from_str(include_str!("../../seed_tags/ada_light_switch.json")).unwrap();
    entry["epc"] = epc.into();
    entry["properties"]["name"] = name.into();
    entry
}

/// Registers a robot as an admin.
pub async fn register_robot(
    server: &TestServer,
    id: &str,
    class: &str,
    capabilities: &[&str],
    max_force: f64,
) {
    let robot = serde_json::json!({
        "id": id, "class": class, "name": id.to_uppercase(),
        "capabilities": capabilities, "limits": { "max_force": max_force }
    });
    let response = server.put(&format!("/api/v1/robots/{id}"), &server.admin, &robot, None).await;
    assert!(response.status().is_success(), "{}", response.text().await.unwrap());
}

/// A valid trial body.
pub fn trial(
    id: &str,
    epc: &str,
    robot: &str,
    action: &str,
    behavior: &str,
    outcome: &str,
) -> Value {
    serde_json::json!({
        "id": id, "epc": epc, "robot": robot, "action": action, "behavior": behavior,
        "started_at": "2026-11-22T10:00:00Z", "finished_at": "2026-11-22T10:00:30Z",
        "outcome": outcome, "confirmed": null, "detector": { "kind": "test" },
        "forces": [], "measurements": {}
    })
}
