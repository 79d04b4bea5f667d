//! Experiments apart: a trial says why it was made, and success rates, reliability and
//! learning count real use unless asked to include experiments and tests.

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::StatusCode;
use serde_json::{Value, json};

/// Records a drawer-opening trial of `el-e-1`; `purpose` left out when `None`.
async fn record(
    server: &TestServer,
    robot: &str,
    outcome: &str,
    displacement: f64,
    purpose: Option<&str>,
) -> String {
    let id = uuid();
    let mut body = trial(&id, DRAWER, "el-e-1", "open", "pull_open", outcome);
    body["measurements"] = json!({ "displacement": displacement });
    if let Some(purpose) = purpose {
        body["purpose"] = purpose.into();
    }
    let response = server.put(&format!("/api/v1/trials/{id}"), robot, &body, None).await;
    assert_eq!(response.status(), StatusCode::CREATED);
    id
}

fn open_group(stats: &Value) -> &Value {
    let groups = stats["groups"].as_array().unwrap();
    groups.iter().find(|g| g["action"] == "open").unwrap_or_else(|| panic!("{stats}"))
}

#[tokio::test]
async fn experiments_and_tests_count_only_when_asked() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let mut feed = SseClient::connect(&server, &server.admin, None).await;
    // Real use: 20 pulls of 35 cm, all fine. The drawer becomes reliable.
    for _ in 0..20 {
        record(&server, &robot, "success", 0.35, None).await;
    }
    let became = feed.until("reliability_changed", "epc", DRAWER).await;
    assert_eq!(became.data["reliable"], true);
    // An experiment pulls a drawer wedged at 10 cm and one that is stuck; a test fails.
    for _ in 0..25 {
        record(&server, &robot, "success", 0.10, Some("experiment")).await;
    }
    for _ in 0..10 {
        record(&server, &robot, "failure", 0.0, Some("experiment")).await;
    }
    let last = record(&server, &robot, "failure", 0.0, Some("test")).await;

    // The registry's own verdict, which ranks robots for tasks, did not move.
    loop {
        let event = feed.next(std::time::Duration::from_secs(10)).await.expect("the trial");
        assert_ne!(event.kind, "reliability_changed", "{event:?}");
        if event.kind == "trial_recorded" && event.data["trial"] == last.as_str() {
            break;
        }
    }
    // Nor did what robots are told to pull: the experiment's 10 cm are not learned.
    let effective: Value = server
        .get(&format!("/api/v1/robots/el-e-1/tags/{DRAWER}"), &robot)
        .await
        .json()
        .await
        .unwrap();
    assert_eq!(effective["entry"]["behaviors"]["pull_open"]["pull_distance"], 0.35);

    let stats = server.get_json(&format!("/api/v1/tags/{DRAWER}/stats")).await;
    assert_eq!(stats["counted"], json!(["use"]));
    assert_eq!(stats["not_counted"], json!({ "experiment": 35, "test": 1 }));
    let open = open_group(&stats);
    assert_eq!(open["attempts"], 20);
    assert_eq!(open["success_rate"], 1.0);
    assert_eq!(open["reliable"], true);
    assert_eq!(open["learned"]["/behaviors/pull_open/pull_distance"]["value"], 0.35);

    let stats = server.get_json(&format!("/api/v1/tags/{DRAWER}/stats?include=experiment")).await;
    assert_eq!(stats["counted"], json!(["use", "experiment"]));
    assert_eq!(stats["not_counted"], json!({ "test": 1 }));
    let open = open_group(&stats);
    assert_eq!(open["attempts"], 55);
    assert_eq!(open["detected_successes"], 45);
    assert_eq!(open["reliable"], false, "10 failures among the latest 50 attempts");

    let stats =
        server.get_json(&format!("/api/v1/tags/{DRAWER}/stats?include=experiment,test")).await;
    assert_eq!(stats["counted"], json!(["use", "experiment", "test"]));
    assert_eq!(stats["not_counted"], json!({}));
    assert_eq!(open_group(&stats)["attempts"], 56);

    let refused = server.get(&format!("/api/v1/tags/{DRAWER}/stats?include=demo"), &robot).await;
    let problem = problem(refused, StatusCode::BAD_REQUEST).await;
    assert!(problem["detail"].as_str().unwrap().contains("\"demo\" is not one"), "{problem}");
}

#[tokio::test]
async fn a_trial_keeps_its_purpose_and_a_retry_must_repeat_it() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let put = |body: Value| {
        let (server, robot) = (&server, robot.clone());
        async move {
            let path = format!("/api/v1/trials/{}", body["id"].as_str().unwrap());
            server.put(&path, &robot, &body, None).await
        }
    };

    let id = uuid();
    let mut experiment = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "failure");
    experiment["purpose"] = "experiment".into();
    let stored: Value = put(experiment.clone()).await.json().await.unwrap();
    assert_eq!(stored["purpose"], "experiment");
    assert_eq!(put(experiment.clone()).await.status(), StatusCode::OK);
    experiment["purpose"] = "test".into();
    problem(put(experiment.clone()).await, StatusCode::CONFLICT).await;
    experiment["purpose"] = "demo".into();
    let invalid = problem(put(experiment).await, StatusCode::UNPROCESSABLE_ENTITY).await;
    assert_eq!(pointers(&invalid), ["/purpose"]);

    // Real use goes without saying: sent with or without it, it is the same trial.
    let id = uuid();
    let plain = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "success");
    assert_eq!(put(plain.clone()).await.status(), StatusCode::CREATED);
    let mut spelled_out = plain.clone();
    spelled_out["purpose"] = "use".into();
    assert_eq!(put(spelled_out).await.status(), StatusCode::OK);
    let stored = server.get_json(&format!("/api/v1/trials/{id}")).await;
    assert_eq!(stored["purpose"], "use");

    let listed = server.get_json(&format!("/api/v1/trials?epc={DRAWER}&purpose=experiment")).await;
    let purposes: Vec<&Value> =
        listed["items"].as_array().unwrap().iter().map(|t| &t["purpose"]).collect();
    assert_eq!(purposes, [&json!("experiment")]);
    let listed = server.get_json(&format!("/api/v1/trials?epc={DRAWER}&purpose=use")).await;
    assert_eq!(listed["items"][0]["id"], id.as_str());
    assert_eq!(listed["items"].as_array().unwrap().len(), 1);
    let refused = server.get("/api/v1/trials?purpose=demo", &server.admin).await;
    let problem = problem(refused, StatusCode::BAD_REQUEST).await;
    assert!(problem["detail"].as_str().unwrap().contains("\"demo\""), "{problem}");
}
