//! The change feed resuming across a restart without gaps or repeats, and the metrics counting
//! requests by route.

use std::time::Duration;

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};

#[tokio::test]
async fn the_change_feed_resumes_without_gaps_or_repeats_across_a_restart() {
    let server = TestServer::start().await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let mut feed = SseClient::connect(&server, &server.admin, None).await;
    let mut written = Vec::new();
    let write = |n: usize| {
        let server = &server;
        let robot = robot.clone();
        async move {
            let mut ids = Vec::new();
            for _ in 0..n {
                let id = uuid();
                let body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
                assert_eq!(
                    server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await.status(),
                    StatusCode::CREATED
                );
                ids.push(id);
            }
            ids
        }
    };
    written.extend(write(5).await);
    let mut seen = Vec::new();
    let mut last = 0;
    while seen.len() < 5 {
        let event = feed.next(Duration::from_secs(10)).await.expect("live events arrive");
        assert!(event.id > last, "ids are monotonic");
        last = event.id;
        if event.kind == "trial_recorded" {
            seen.push(event.data["trial"].as_str().unwrap().to_owned());
        }
    }
    drop(feed);
    written.extend(write(7).await);

    let (restarted, _stop) = server.restarted().await;
    let resumed = reqwest::Client::new()
        .get(format!("{restarted}/api/v1/events"))
        .bearer_auth(&server.admin)
        .header("last-event-id", last.to_string())
        .send()
        .await
        .unwrap();
    let mut feed = SseClient { response: resumed, buffer: String::new() };
    while let Some(event) = feed.next(Duration::from_secs(2)).await {
        if event.kind == "trial_recorded" {
            seen.push(event.data["trial"].as_str().unwrap().to_owned());
        }
        if seen.len() == written.len() {
            break;
        }
    }
    assert_eq!(seen, written, "each trial exactly once, in order");

    let robot_feed = SseClient::connect(&server, &robot, Some(0)).await;
    drop(robot_feed);
    problem(
        server
            .request(Method::GET, "/api/v1/events", Some(&server.admin))
            .header("last-event-id", "abc")
            .send()
            .await
            .unwrap(),
        StatusCode::BAD_REQUEST,
    )
    .await;
}

#[tokio::test]
async fn metrics_count_requests_by_route() {
    let server = TestServer::start().await;
    server.get(&format!("/api/v1/tags/{ADA_SWITCH}"), &server.admin).await;
    let text =
        server.request(Method::GET, "/metrics", None).send().await.unwrap().text().await.unwrap();
    assert!(
        text.contains(
            r#"pps_http_requests_total{route="/api/v1/tags/{epc}",method="GET",status="200"} 1"#
        ),
        "{text}"
    );
    assert!(text.contains("pps_http_request_duration_seconds_bucket"));
    assert!(text.contains("pps_trials_recorded_total 0"));
}
