//! A robot flooding the task queue, against the real `pps-server serve` process: 199 queued
//! tasks it cannot do and 200 long-poll claims from it at once. It waits with a few claims,
//! the rest are refused at once, and the waiting claims read the queue once each while nothing
//! changes. The server runs with `--max-tasks-per-robot 1`, and a second task is refused.

use std::time::Duration;

use pps_test_kit::Registry;
use pps_test_kit::fixtures::DRAWER;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

const FLIP_SWITCH: &str = "355AB1C60000001000000001";

/// A number from the registry's metrics.
async fn metric(registry: &Registry, name: &str) -> u64 {
    let metrics = registry.request(Method::GET, "/metrics", "").send().await.unwrap();
    let text = metrics.text().await.unwrap();
    let value = text.lines().find_map(|l| l.strip_prefix(name)?.strip_prefix(' '));
    value.and_then(|n| n.parse().ok()).unwrap_or_else(|| panic!("no metric {name}"))
}

async fn ask(registry: &Registry, body: Value) -> Value {
    let (status, task) =
        registry.call(Method::POST, "/api/v1/tasks", &registry.admin_token, Some(&body), &[]).await;
    assert_eq!(status, StatusCode::CREATED, "{task}");
    task
}

#[tokio::test]
async fn two_hundred_waiting_claims_of_one_robot_cost_four_looks() {
    let registry = Registry::with_flags(&["--max-tasks-per-robot", "1"]);
    let robot = json!({ "class": "el-e", "name": "Pusher", "capabilities": ["push"] });
    let (status, _) = registry
        .call(Method::PUT, "/api/v1/robots/pusher-1", &registry.admin_token, Some(&robot), &[])
        .await;
    assert!(status.is_success());
    let token = registry.token("robot", "pusher-1");

    // Every task on the feed before anyone waits: none of them may wake a waiting claim later.
    let mut feed = registry.request(Method::GET, "/api/v1/events", &registry.admin_token);
    feed = feed.timeout(Duration::from_secs(60));
    let mut feed = feed.send().await.unwrap();
    let mut last = Value::Null;
    for _ in 0..199 {
        last = ask(&registry, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    }
    let last = last["id"].as_str().unwrap().to_owned();
    let mut seen = String::new();
    while !seen.contains(&last) {
        let chunk = feed.chunk().await.unwrap().expect("the feed stays open");
        seen.push_str(&String::from_utf8_lossy(&chunk));
    }
    let looks_before = metric(&registry, "pps_task_looks_total").await;

    let claims: Vec<_> = (0..200)
        .map(|_| {
            let request = registry.request(
                Method::POST,
                "/api/v1/robots/pusher-1/tasks/claim?wait=2",
                &token,
            );
            tokio::spawn(async move { request.send().await.unwrap() })
        })
        .collect();
    let (mut waited, mut refused) = (0, 0);
    for claim in claims {
        let response = claim.await.unwrap();
        match response.status() {
            StatusCode::NO_CONTENT => waited += 1,
            StatusCode::TOO_MANY_REQUESTS => {
                assert_eq!(response.headers()["retry-after"], "5");
                refused += 1;
            }
            other => panic!("a claim answered {other}"),
        }
    }
    assert_eq!((waited, refused), (4, 196), "4 claims wait, the others are refused at once");
    let looks = metric(&registry, "pps_task_looks_total").await - looks_before;
    assert_eq!(looks, 4, "each waiting claim read the queue once: nothing changed");

    // The task meant for it, behind all 199, and no second one at once.
    for _ in 0..2 {
        ask(&registry, json!({ "epc": DRAWER, "action": "close" })).await;
    }
    let path = "/api/v1/robots/pusher-1/tasks/claim";
    let (status, got) = registry.call(Method::POST, path, &token, None, &[]).await;
    assert_eq!(status, StatusCode::OK, "{got}");
    assert_eq!(got["epc"], DRAWER);
    let (status, refused) = registry.call(Method::POST, path, &token, None, &[]).await;
    assert_eq!(status, StatusCode::CONFLICT, "{refused}");
    let detail = refused["detail"].as_str().unwrap();
    assert!(detail.contains(got["id"].as_str().unwrap()), "{detail}");
}
