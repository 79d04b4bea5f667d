//! What the registry learns from trials: per-class stats, learned values within their bounds,
//! and the reliable flag changing.

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::StatusCode;
use serde_json::{Value, json};

#[tokio::test]
async fn stats_and_learned_values_follow_the_trials() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let effective = format!("/api/v1/robots/el-e-1/tags/{DRAWER}");
    let before: Value = server.get(&effective, &robot).await.json().await.unwrap();
    assert_eq!(before["entry"]["behaviors"]["pull_open"]["pull_distance"], 0.3);
    // Another robot of the class follows the feed: it hears that its entry changed too.
    register_robot(&server, "el-e-2", "el-e", ALL, 15.0).await;
    let sibling = server.token(Role::Robot, "el-e-2").await;
    let mut feed = SseClient::connect(&server, &sibling, None).await;
    for (displacement, outcome) in
        [(0.34, "success"), (0.36, "success"), (0.05, "failure"), (0.35, "success")]
    {
        let id = uuid();
        let mut body = trial(&id, DRAWER, "el-e-1", "open", "pull_open", outcome);
        body["measurements"] = json!({ "displacement": displacement });
        assert_eq!(
            server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await.status(),
            StatusCode::CREATED
        );
    }
    let after: Value = server.get(&effective, &robot).await.json().await.unwrap();
    assert_eq!(
        after["entry"]["behaviors"]["pull_open"]["pull_distance"], 0.35,
        "the median of the successful pulls"
    );
    assert_eq!(after["provenance"]["/behaviors/pull_open/pull_distance"], "learned");
    let learned = feed.until("learned_changed", "epc", DRAWER).await;
    assert_eq!(learned.data["robot_class"], "el-e");

    let stats = server.get_json(&format!("/api/v1/tags/{DRAWER}/stats")).await;
    let group = &stats["groups"][0];
    assert_eq!(group["action"], "open");
    assert_eq!(group["robot_class"], "el-e");
    assert_eq!(group["attempts"], 4);
    assert_eq!(group["detected_successes"], 3);
    assert_eq!(group["success_rate"], 0.75);
    assert_eq!(group["reliable"], false);
    assert_eq!(group["learned"]["/behaviors/pull_open/pull_distance"]["value"], 0.35);

    // Closing the drawer pushes: what pulling it open taught is not listed under close.
    let id = uuid();
    let close = trial(&id, DRAWER, "el-e-1", "close", "push_closed", "success");
    let recorded = server.put(&format!("/api/v1/trials/{id}"), &robot, &close, None).await;
    assert_eq!(recorded.status(), StatusCode::CREATED);
    let stats = server.get_json(&format!("/api/v1/tags/{DRAWER}/stats")).await;
    let close =
        stats["groups"].as_array().unwrap().iter().find(|g| g["action"] == "close").unwrap();
    assert_eq!(close["learned"], json!({}), "{stats}");
}

#[tokio::test]
async fn a_tag_that_stops_being_reliable_says_so() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let mut feed = SseClient::connect(&server, &server.admin, None).await;
    let record = |outcome: &'static str| {
        let server = &server;
        let robot = robot.clone();
        async move {
            let id = uuid();
            let body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", outcome);
            assert_eq!(
                server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await.status(),
                StatusCode::CREATED
            );
        }
    };
    for _ in 0..20 {
        record("success").await;
    }
    let became = feed.until("reliability_changed", "epc", ADA_SWITCH).await;
    assert_eq!(became.data["reliable"], true);
    for _ in 0..3 {
        record("failure").await;
    }
    let stopped = feed.until("reliability_changed", "epc", ADA_SWITCH).await;
    assert_eq!(stopped.data["reliable"], false);
    assert_eq!(stopped.data["action"], "on");
    assert_eq!(stopped.data["robot_class"], "el-e");
}
