//! Effective entries through HTTP: each robot class's parameters with their provenance, and
//! revalidation by ETag.

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

#[tokio::test]
async fn two_robot_classes_get_their_own_parameters_with_provenance() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    register_robot(&server, "pr2-1", "pr2", ALL, 40.0).await;
    let ele = server.token(Role::Robot, "el-e-1").await;
    let pr2 = server.token(Role::Robot, "pr2-1").await;
    let path = |robot: &str| format!("/api/v1/robots/{robot}/tags/{ADA_SWITCH}");

    let for_ele: Value = server.get(&path("el-e-1"), &ele).await.json().await.unwrap();
    let for_pr2: Value = server.get(&path("pr2-1"), &pr2).await.json().await.unwrap();
    assert_eq!(for_ele["entry"]["behaviors"]["push_top"]["gripper_deg"], 5);
    assert_eq!(for_ele["provenance"]["/behaviors/push_top/gripper_deg"], "class:el-e");
    assert_eq!(for_pr2["entry"]["behaviors"]["push_top"]["gripper_deg"], 10);
    assert_eq!(for_pr2["provenance"]["/behaviors/push_top/gripper_deg"], "base");
    assert_eq!(for_ele["robot"], "el-e-1");
    assert_eq!(for_ele["revision"], 1);
    assert_eq!(for_ele["unavailable_actions"], json!([]));

    // A robot override wins over its class.
    let mut entry = server.get_json(&format!("/api/v1/tags/{ADA_SWITCH}")).await;
    entry["behaviors"]["push_top"]["robots"]["el-e-1"] = json!({ "gripper_deg": 7 });
    let saved = server
        .put(
            &format!("/api/v1/tags/{ADA_SWITCH}"),
            &server.admin,
            &entry,
            Some(("if-match", "\"r1\"")),
        )
        .await;
    assert_eq!(saved.status(), StatusCode::OK);
    let for_ele: Value = server.get(&path("el-e-1"), &ele).await.json().await.unwrap();
    assert_eq!(
        for_ele["entry"]["behaviors"]["push_top"]["gripper_deg"], 7,
        "the change is visible at once"
    );
    assert_eq!(for_ele["provenance"]["/behaviors/push_top/gripper_deg"], "robot:el-e-1");

    problem(server.get(&path("el-e-1"), &pr2).await, StatusCode::FORBIDDEN).await;
    assert_eq!(
        server.get(&path("el-e-1"), &server.admin).await.status(),
        StatusCode::OK,
        "caretakers may look"
    );
}

#[tokio::test]
async fn effective_entries_revalidate_with_etags() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let path = format!("/api/v1/robots/el-e-1/tags/{DRAWER}");
    let first = server.get(&path, &robot).await;
    let etag = first.headers()["etag"].to_str().unwrap().to_owned();
    let again = server
        .request(Method::GET, &path, Some(&robot))
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(again.status(), StatusCode::NOT_MODIFIED);
    register_robot(&server, "el-e-1", "el-e", &["push"], 15.0).await;
    let changed = server
        .request(Method::GET, &path, Some(&robot))
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(changed.status(), StatusCode::OK, "a robot's capabilities shape its entry");
    let changed: Value = changed.json().await.unwrap();
    assert_eq!(changed["unavailable_actions"][0]["action"], "open");
}
