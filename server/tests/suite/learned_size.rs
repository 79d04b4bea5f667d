//! Tag sizes learned from confirmed reads (issue 34): the trials' `tag_size` teach each tag's
//! size once three confirmed visits of real use carry one, and the effective entry carries it at
//! `/properties/tag_size` with provenance `learned`, unless the entry has a size of its own.

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

/// The drawer's towel as a robot measured it.
fn towel(width: f64, height: f64) -> Value {
    json!({ "width": width, "height": height })
}

/// Records a drawer trial by `el-e-1` carrying `size`, with the person's `confirmed` verdict;
/// its id.
async fn visit(
    server: &TestServer,
    robot: &str,
    size: Value,
    confirmed: Value,
    purpose: &str,
) -> String {
    let id = uuid();
    let mut body = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "success");
    body["tag_size"] = size;
    body["confirmed"] = confirmed;
    body["purpose"] = json!(purpose);
    let sent = server.put(&format!("/api/v1/trials/{id}"), robot, &body, None).await;
    assert_eq!(sent.status(), StatusCode::CREATED, "{}", sent.text().await.unwrap());
    id
}

async fn effective(server: &TestServer, robot: &str, epc: &str) -> Value {
    let path = format!("/api/v1/robots/el-e-1/tags/{epc}");
    let response = server.get(&path, robot).await;
    assert_eq!(response.status(), StatusCode::OK, "GET {path}");
    response.json().await.unwrap()
}

/// A registry whose drawer has learned its size from three confirmed visits.
async fn learned_drawer() -> (TestServer, String) {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    for (width, height) in [(0.158, 0.236), (0.163, 0.241), (0.171, 0.239)] {
        visit(&server, &robot, towel(width, height), json!(true), "use").await;
    }
    (server, robot)
}

#[tokio::test]
async fn three_confirmed_visits_teach_a_tag_its_size_and_nothing_else_does() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    // An experiment's, a refuted visit's and one awaiting its verdict teach nothing...
    visit(&server, &robot, towel(0.4, 0.5), json!(true), "experiment").await;
    visit(&server, &robot, towel(0.4, 0.5), json!(false), "use").await;
    let waiting = visit(&server, &robot, towel(0.165, 0.242), Value::Null, "use").await;
    // ...and two confirmed ones are too few.
    visit(&server, &robot, towel(0.158, 0.236), json!(true), "use").await;
    visit(&server, &robot, towel(0.163, 0.241), json!(true), "use").await;
    let entry = effective(&server, &robot, DRAWER).await;
    assert!(entry["entry"]["properties"].get("tag_size").is_none(), "{entry}");
    assert_eq!(server.stats(DRAWER, None).await["learned_size"], Value::Null);

    visit(&server, &robot, towel(0.171, 0.239), json!(true), "use").await;
    let entry = effective(&server, &robot, DRAWER).await;
    assert_eq!(entry["entry"]["properties"]["tag_size"], towel(0.163, 0.239), "the medians");
    assert_eq!(entry["provenance"]["/properties/tag_size/width"], "learned");
    assert_eq!(entry["provenance"]["/properties/tag_size/height"], "learned");
    let stats = server.stats(DRAWER, None).await;
    assert_eq!(stats["learned_size"], json!({ "width": 0.163, "height": 0.239, "trials": 3 }));

    // The person's later yes makes the waiting visit teach too.
    let path = format!("/api/v1/trials/{waiting}");
    let confirmed = server
        .request(Method::PATCH, &path, Some(&server.admin))
        .json(&json!({ "confirmed": true }))
        .send()
        .await
        .unwrap();
    assert_eq!(confirmed.status(), StatusCode::OK);
    let stats = server.stats(DRAWER, None).await;
    assert_eq!(stats["learned_size"], json!({ "width": 0.164, "height": 0.24, "trials": 4 }));
    // Another tag learned nothing from the drawer's visits.
    let switch = effective(&server, &robot, ADA_SWITCH).await;
    assert!(switch["entry"]["properties"].get("tag_size").is_none(), "{switch}");
}

#[tokio::test]
async fn a_size_a_caretaker_measured_stands() {
    let (server, robot) = learned_drawer().await;
    server.edit_tag(DRAWER, |entry| entry["properties"]["tag_size"] = towel(0.16, 0.24)).await;
    let entry = effective(&server, &robot, DRAWER).await;
    assert_eq!(entry["entry"]["properties"]["tag_size"], towel(0.16, 0.24));
    assert_eq!(entry["provenance"]["/properties/tag_size/width"], "base");
    // Still learned, and shown as such, for when the caretaker's size is taken away.
    assert_eq!(server.stats(DRAWER, None).await["learned_size"]["trials"], 3);
}

#[tokio::test]
async fn a_size_out_of_bounds_is_refused_and_stores_nothing() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    for (size, field) in [
        (towel(1.4, 0.24), "/tag_size/width"),
        (towel(0.16, 0.004), "/tag_size/height"),
        (json!({ "width": 0.16 }), "/tag_size/height"),
    ] {
        let id = uuid();
        let mut body = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "success");
        body["tag_size"] = size;
        body["confirmed"] = json!(true);
        let response = server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await;
        let refused = problem(response, StatusCode::UNPROCESSABLE_ENTITY).await;
        assert_eq!(pointers(&refused), [field], "{refused}");
    }
    assert_eq!(server.trials().await, Vec::<Value>::new(), "nothing stored");
}

#[tokio::test]
async fn retagging_moves_the_learned_size() {
    let (server, robot) = learned_drawer().await;
    let new = "E20034120000000000007777";
    let moved = server
        .request(Method::POST, &format!("/api/v1/tags/{DRAWER}/retag"), Some(&server.admin))
        .json(&json!({ "new_epc": new }))
        .send()
        .await
        .unwrap();
    assert_eq!(moved.status(), StatusCode::OK);
    let entry = effective(&server, &robot, new).await;
    assert_eq!(entry["entry"]["properties"]["tag_size"], towel(0.163, 0.239));
    assert_eq!(entry["provenance"]["/properties/tag_size/height"], "learned");
    assert_eq!(server.stats(new, None).await["learned_size"]["trials"], 3);
}
