//! A tag's life beyond its entry: unknown EPCs in the inbox until registered, retagging a worn tag
//! (entry, trials and learned values move), and a retired EPC never coming back.

use std::time::Duration;

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

#[tokio::test]
async fn unknown_epcs_land_in_the_inbox_until_registered() {
    let server = TestServer::start().await;
    let a = server.token(Role::Robot, "el-e-1").await;
    let b = server.token(Role::Robot, "el-e-2").await;
    let epc = "E2003412000000000000ABCD";
    for (robot, token) in [("el-e-1", &a), ("el-e-2", &b), ("el-e-1", &a)] {
        let response = server.get(&format!("/api/v1/robots/{robot}/tags/{epc}"), token).await;
        let body = problem(response, StatusCode::NOT_FOUND).await;
        assert!(body["detail"].as_str().unwrap().contains("inbox"));
    }
    // The sightings are flushed in the background: wait until all three are in.
    let item = wait_until(Duration::from_secs(1), "the inbox to show all three", || async {
        let inbox = server.get_json("/api/v1/inbox").await;
        inbox["items"].as_array().unwrap().first().filter(|i| i["count"] == 3).cloned()
    })
    .await;
    assert_eq!(item["epc"], epc);
    assert_eq!(item["count"], 3);
    assert_eq!(item["robots"], json!(["el-e-1", "el-e-2"]));
    problem(server.get("/api/v1/inbox", &a).await, StatusCode::FORBIDDEN).await;

    let created = server
        .put(
            &format!("/api/v1/tags/{epc}"),
            &server.admin,
            &new_entry(epc, "found"),
            Some(("if-none-match", "*")),
        )
        .await;
    assert_eq!(created.status(), StatusCode::CREATED);
    assert_eq!(server.get_json("/api/v1/inbox").await["items"], json!([]));
}

#[tokio::test]
async fn retag_moves_entry_trials_and_learned_values() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let id = uuid();
    let mut body = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "success");
    body["measurements"] = json!({ "displacement": 0.33 });
    assert_eq!(
        server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await.status(),
        StatusCode::CREATED
    );

    let new = "E20034120000000000007777";
    let moved = server
        .request(Method::POST, &format!("/api/v1/tags/{DRAWER}/retag"), Some(&server.admin))
        .json(&json!({ "new_epc": new }))
        .send()
        .await
        .unwrap();
    assert_eq!(moved.status(), StatusCode::OK);
    let moved: Value = moved.json().await.unwrap();
    assert_eq!(moved["epc"], new);
    assert_eq!(moved["revision"], 2);

    let old = problem(
        server.get(&format!("/api/v1/robots/el-e-1/tags/{DRAWER}"), &robot).await,
        StatusCode::NOT_FOUND,
    )
    .await;
    assert!(old["detail"].as_str().unwrap().contains(new), "{old}");
    let effective: Value = server
        .get(&format!("/api/v1/robots/el-e-1/tags/{new}"), &robot)
        .await
        .json()
        .await
        .unwrap();
    assert_eq!(effective["entry"]["behaviors"]["pull_open"]["pull_distance"], 0.33);
    let trials = server.get_json(&format!("/api/v1/trials?epc={new}")).await;
    assert_eq!(trials["items"].as_array().unwrap().len(), 1);
    let history = server.get_json(&format!("/api/v1/tags/{new}/revisions")).await;
    assert_eq!(history["items"].as_array().unwrap().len(), 2);

    let again = server
        .request(Method::POST, &format!("/api/v1/tags/{new}/retag"), Some(&server.admin))
        .json(&json!({ "new_epc": ADA_SWITCH }))
        .send()
        .await
        .unwrap();
    problem(again, StatusCode::CONFLICT).await;
    let id = uuid();
    let late = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "success");
    let response = server.put(&format!("/api/v1/trials/{id}"), &robot, &late, None).await;
    let body = problem(response, StatusCode::UNPROCESSABLE_ENTITY).await;
    assert!(body["errors"][0]["message"].as_str().unwrap().contains(new));
}

#[tokio::test]
async fn a_retired_epc_is_never_registered_again() {
    let server = TestServer::start().await;
    let new = "E20034120000000000007778";
    let moved = server
        .request(Method::POST, &format!("/api/v1/tags/{ADA_SWITCH}/retag"), Some(&server.admin))
        .json(&json!({ "new_epc": new }))
        .send()
        .await
        .unwrap();
    assert_eq!(moved.status(), StatusCode::OK);
    let reuse = server
        .put(
            &format!("/api/v1/tags/{ADA_SWITCH}"),
            &server.admin,
            &new_entry(ADA_SWITCH, "again"),
            Some(("if-none-match", "*")),
        )
        .await;
    let body = problem(reuse, StatusCode::CONFLICT).await;
    assert!(body["detail"].as_str().unwrap().contains(new), "{body}");
}

#[tokio::test]
async fn a_tag_retagged_seventy_times_is_found_from_its_first_epc() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let mut current = DRAWER.to_owned();
    for n in 1..=70 {
        let next = format!("E2003412000000000000{n:04X}");
        let moved = server
            .request(Method::POST, &format!("/api/v1/tags/{current}/retag"), Some(&server.admin))
            .json(&json!({ "new_epc": next }))
            .send()
            .await
            .unwrap();
        assert_eq!(moved.status(), StatusCode::OK, "retag {n}");
        current = next;
    }
    for retired in [DRAWER.to_owned(), "E20034120000000000000001".to_owned()] {
        let old = problem(
            server.get(&format!("/api/v1/robots/el-e-1/tags/{retired}"), &robot).await,
            StatusCode::NOT_FOUND,
        )
        .await;
        let detail = old["detail"].as_str().unwrap();
        assert!(detail.ends_with(&format!("the tag now has the EPC {current}")), "{detail}");
    }
    let asked = server
        .request(Method::POST, "/api/v1/tasks", Some(&server.admin))
        .json(&json!({ "epc": DRAWER, "action": "open" }))
        .send()
        .await
        .unwrap();
    let refused = problem(asked, StatusCode::UNPROCESSABLE_ENTITY).await;
    assert!(refused.to_string().contains(&format!("on {current}")), "{refused}");
}
