//! The task queue under abuse (DESIGN §8): robots waiting for tasks cost nothing while nothing
//! changes and wait with a few claims at most; a robot finds the task meant for it behind any
//! number it cannot do; tasks nobody took in time expire and say so; one robot holds only a
//! few tasks at once.

use std::time::{Duration, Instant};

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

/// A claim running on its own, as a waiting robot's long poll: its status and body.
fn claiming(
    server: &TestServer,
    token: &str,
    robot: &str,
    wait: f64,
) -> tokio::task::JoinHandle<(StatusCode, Option<Value>)> {
    let url = format!("{}/api/v1/robots/{robot}/tasks/claim?wait={wait}", server.url);
    let token = token.to_owned();
    tokio::spawn(async move {
        let response = reqwest::Client::new().post(url).bearer_auth(token).send().await.unwrap();
        let status = response.status();
        (status, response.json().await.ok())
    })
}

fn id(task: &Value) -> &str {
    task["id"].as_str().unwrap()
}

/// A robot that can only push (no light switch, no lamp), and its token.
async fn pusher(server: &TestServer) -> String {
    register_robot(server, "pusher-1", "el-e", &["push"], 15.0).await;
    server.token(Role::Robot, "pusher-1").await
}

/// Asks for `n` light-switch tasks (a pusher cannot do them) and returns once the registry has
/// seen every one of them go by on its feed, so no robot waiting afterwards is woken by them.
async fn switch_tasks_settled(server: &TestServer, n: usize) {
    let mut feed = SseClient::connect(server, &server.admin, None).await;
    let mut last = Value::Null;
    for _ in 0..n {
        last = asked(server, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    }
    feed.until("task_changed", "task", id(&last)).await;
}

#[tokio::test]
async fn waiting_claims_read_the_queue_only_when_something_changes() {
    let server = TestServer::start().await;
    let token = pusher(&server).await;
    switch_tasks_settled(&server, 199).await;
    let looks_before = metric(&server, "pps_task_looks_total").await.unwrap();

    let waiting: Vec<_> = (0..4).map(|_| claiming(&server, &token, "pusher-1", 1.0)).collect();
    robots_waiting(&server, 4).await;
    let refused = claim(&server, &token, "pusher-1", 1.0).await;
    assert_eq!(refused.headers()["retry-after"], "5");
    let refused = problem(refused, StatusCode::TOO_MANY_REQUESTS).await;
    let detail = refused["detail"].as_str().unwrap();
    assert!(detail.contains("already has 4 claims waiting"), "{detail}");
    for claim in waiting {
        assert_eq!(claim.await.unwrap().0, StatusCode::NO_CONTENT);
    }
    let looks = metric(&server, "pps_task_looks_total").await.unwrap() - looks_before;
    assert_eq!(looks, 4, "one look per claim: nothing changed while they waited");
}

#[tokio::test]
async fn a_waiting_claim_looks_again_when_what_its_robot_can_do_changes() {
    let server = TestServer::start().await;
    let token = pusher(&server).await;
    switch_tasks_settled(&server, 3).await;
    let waiting = claiming(&server, &token, "pusher-1", 20.0);
    robots_waiting(&server, 1).await;
    let asked_at = Instant::now();
    register_robot(&server, "pusher-1", "el-e", &["push", "light_switch"], 15.0).await;
    let (status, task) = waiting.await.unwrap();
    assert_eq!(status, StatusCode::OK, "the new ability woke the waiting claim");
    assert!(asked_at.elapsed() < Duration::from_secs(5), "at once, not at the end of the wait");
    assert_eq!(task.unwrap()["epc"], FLIP_SWITCH);
}

#[tokio::test]
async fn a_task_meant_for_a_robot_is_found_behind_two_hundred_it_cannot_do() {
    let server = TestServer::start().await;
    let token = pusher(&server).await;
    for _ in 0..200 {
        asked(&server, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    }
    let drawer = asked(&server, json!({ "epc": DRAWER, "action": "close" })).await;
    let response = claim(&server, &token, "pusher-1", 0.0).await;
    assert_eq!(response.status(), StatusCode::OK, "the drawer task is the pusher's");
    let got: Value = response.json().await.unwrap();
    assert_eq!(got["id"], drawer["id"]);
    assert_eq!(got["claimed_by"], "pusher-1");
}

#[tokio::test]
async fn one_robot_holds_two_tasks_at_most_and_the_next_goes_to_another() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 40.0).await;
    register_robot(&server, "el-e-2", "el-e", ALL, 40.0).await;
    let (first, second) =
        (server.token(Role::Robot, "el-e-1").await, server.token(Role::Robot, "el-e-2").await);
    let mut held = Vec::new();
    for _ in 0..3 {
        asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    }
    for _ in 0..2 {
        let response = claim(&server, &first, "el-e-1", 0.0).await;
        assert_eq!(response.status(), StatusCode::OK);
        held.push(response.json::<Value>().await.unwrap());
    }
    let refused = problem(claim(&server, &first, "el-e-1", 5.0).await, StatusCode::CONFLICT).await;
    let detail = refused["detail"].as_str().unwrap();
    assert!(detail.contains(id(&held[0])) && detail.contains(id(&held[1])), "{detail}");
    assert!(detail.contains("finish or decline one"), "{detail}");
    let response = claim(&server, &second, "el-e-2", 0.0).await;
    assert_eq!(response.status(), StatusCode::OK, "the third task goes to the other robot");

    let path = format!("/api/v1/tasks/{}/decline", id(&held[0]));
    let request = server.request(Method::POST, &path, Some(&first));
    let declined = request.json(&json!({ "reason": "its arm is stuck" })).send().await.unwrap();
    assert_eq!(declined.status(), StatusCode::OK);
    let response = claim(&server, &first, "el-e-1", 0.0).await;
    assert_eq!(response.status(), StatusCode::NO_CONTENT, "below the cap again; nothing left");
}

#[tokio::test]
async fn a_task_nobody_did_in_time_expires_and_says_so() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 40.0).await;
    register_robot(&server, "el-e-2", "el-e", ALL, 40.0).await;
    let token = server.token(Role::Robot, "el-e-1").await;
    let to_expiry = Duration::from_secs(10);
    assert!(server.config.lease > to_expiry, "the lease outlives the expiry");
    let soon = pps_server::clock::format(server.now() + to_expiry);
    let mut feed = SseClient::connect(&server, &server.admin, None).await;
    let untaken = asked(
        &server,
        json!({ "epc": LAMP, "action": "on", "robot": "el-e-2", "expires_at": soon }),
    )
    .await;
    assert_eq!(untaken["expires_at"], soon);
    assert_eq!(untaken["expired"], false);
    let abandoned = asked(
        &server,
        json!({ "epc": LAMP, "action": "on", "robot": "el-e-1", "expires_at": soon }),
    )
    .await;
    let later = asked(&server, json!({ "epc": LAMP, "action": "off", "robot": "el-e-1" })).await;
    let created = pps_server::clock::parse(later["created_at"].as_str().unwrap()).unwrap();
    let expires = pps_server::clock::parse(later["expires_at"].as_str().unwrap()).unwrap();
    assert_eq!(expires - created, time::Duration::DAY, "a day unless asked otherwise");

    // el-e-1 takes one and goes quiet: the other one expires untaken; the one it holds does
    // not expire while its lease lives, and does once the lease runs out.
    let response = claim(&server, &token, "el-e-1", 0.0).await;
    assert_eq!(response.json::<Value>().await.unwrap()["id"], abandoned["id"]);
    server.advance(to_expiry);
    let expired = |task: &Value, words: &'static str| {
        let (id, server) = (id(task).to_owned(), &server);
        async move {
            let read = server.get_json(&format!("/api/v1/tasks/{id}")).await;
            assert_eq!(
                (read["state"].as_str(), read["expired"].as_bool()),
                (Some("cancelled"), Some(true))
            );
            assert!(read["reason"].as_str().unwrap().starts_with(words), "{read}");
        }
    };
    let event = loop {
        let event = feed.until("task_changed", "task", id(&untaken)).await;
        if event.data["state"] != "queued" {
            break event;
        }
    };
    assert_eq!(event.data["state"], "cancelled");
    expired(&untaken, "it expired: no robot took it by").await;
    let held = server.get_json(&format!("/api/v1/tasks/{}", id(&abandoned))).await;
    assert_eq!(held["state"], "claimed", "held under a live lease past its expiry");
    server.advance(server.config.lease - to_expiry);
    let event = loop {
        let event = feed.until("task_changed", "task", id(&abandoned)).await;
        if event.data["state"] != "queued" && event.data["state"] != "claimed" {
            break event;
        }
    };
    assert_eq!(event.data["state"], "cancelled");
    expired(&abandoned, "it expired: no robot finished it by").await;
    let response = claim(&server, &token, "el-e-1", 0.0).await;
    assert_eq!(response.json::<Value>().await.unwrap()["id"], later["id"], "not an expired one");

    let past = "2001-01-01T00:00:00Z";
    let far = pps_server::clock::format(server.now() + time::Duration::days(31));
    for expires_at in [json!(past), json!(far), json!("tomorrow"), json!(7)] {
        let body = json!({ "epc": LAMP, "action": "on", "expires_at": expires_at });
        let refused = problem(ask(&server, body).await, StatusCode::UNPROCESSABLE_ENTITY).await;
        assert_eq!(pointers(&refused), ["/expires_at"], "{expires_at}: {refused}");
    }
}
