//! A registry shared by a fleet: robots, effective entries, the inbox, trials, stats and
//! learning, retagging — through HTTP, with robot tokens bound to their robots.

mod common;

use std::time::{Duration, Instant};

use common::*;
use pps_server::auth::Role;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

const ALL: &[&str] = &["light_switch", "pull_back", "push", "pull_lamp", "drop"];

fn uuid() -> String {
    uuid::Uuid::new_v4().to_string()
}

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
    let deadline = Instant::now() + Duration::from_secs(1);
    let item = loop {
        let inbox = server.get_json("/api/v1/inbox").await;
        // The sightings are flushed in the background: wait until all three are in.
        if let Some(item) = inbox["items"].as_array().unwrap().first().filter(|i| i["count"] == 3) {
            break item.clone();
        }
        assert!(Instant::now() < deadline, "the inbox shows the EPC within a second");
        tokio::time::sleep(Duration::from_millis(50)).await;
    };
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
async fn trials_are_idempotent_and_checked() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let other = server.token(Role::Robot, "el-e-2").await;
    let id = uuid();
    let body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    let path = format!("/api/v1/trials/{id}");

    let first = server.put(&path, &robot, &body, None).await;
    assert_eq!(first.status(), StatusCode::CREATED);
    let stored: Value = first.json().await.unwrap();
    assert!(stored["seq"].as_i64().unwrap() > 0);
    assert!(stored["received_at"].is_string());
    let retry = server.put(&path, &robot, &body, None).await;
    assert_eq!(retry.status(), StatusCode::OK, "a retry over a flaky link is a no-op");
    assert_eq!(retry.json::<Value>().await.unwrap()["seq"], stored["seq"]);
    let mut different = body.clone();
    different["outcome"] = "failure".into();
    problem(server.put(&path, &robot, &different, None).await, StatusCode::CONFLICT).await;

    problem(server.put(&path, &other, &body, None).await, StatusCode::FORBIDDEN).await;
    problem(server.put(&path, &server.admin, &body, None).await, StatusCode::FORBIDDEN).await;

    let check = |body: Value, pointer: &'static str| {
        let server = &server;
        let robot = robot.clone();
        async move {
            let id = body["id"].as_str().unwrap().to_owned();
            let response = server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await;
            let problem = problem(response, StatusCode::UNPROCESSABLE_ENTITY).await;
            assert!(pointers(&problem).contains(&pointer.to_owned()), "{problem}");
        }
    };
    check(
        trial(&uuid(), "E20034120000000000005555", "el-e-1", "on", "push_top", "success"),
        "/epc",
    )
    .await;
    let mut backwards = trial(&uuid(), ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    backwards["finished_at"] = "2026-11-22T09:59:00Z".into();
    check(backwards, "/finished_at").await;
    check(trial(&uuid(), ADA_SWITCH, "el-e-1", "on", "push_top", "great"), "/outcome").await;

    let mut heavy = trial(&uuid(), ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    let sample = json!({ "t": 0.1, "finger": "left", "force": [1.0, 2.0, 3.0] });
    heavy["forces"] = Value::Array(vec![sample.clone(); pps_schema::MAX_FORCE_SAMPLES]);
    let at_cap = server
        .put(&format!("/api/v1/trials/{}", heavy["id"].as_str().unwrap()), &robot, &heavy, None)
        .await;
    assert_eq!(at_cap.status(), StatusCode::CREATED);
    let id = uuid();
    heavy["id"] = id.clone().into();
    heavy["forces"].as_array_mut().unwrap().push(sample);
    problem(
        server.put(&format!("/api/v1/trials/{id}"), &robot, &heavy, None).await,
        StatusCode::PAYLOAD_TOO_LARGE,
    )
    .await;

    // Archived tags take no trials.
    let archived = server
        .request(Method::DELETE, &format!("/api/v1/tags/{DRAWER}"), Some(&server.admin))
        .header("if-match", "\"r1\"")
        .send()
        .await
        .unwrap();
    assert_eq!(archived.status(), StatusCode::OK);
    check(trial(&uuid(), DRAWER, "el-e-1", "open", "pull_open", "success"), "/epc").await;
}

#[tokio::test]
async fn verdicts_are_set_later_and_lists_filter() {
    let server = TestServer::start().await;
    let a = server.token(Role::Robot, "el-e-1").await;
    let b = server.token(Role::Robot, "el-e-2").await;
    let mut ids = Vec::new();
    for (token, robot, outcome) in
        [(&a, "el-e-1", "success"), (&b, "el-e-2", "failure"), (&a, "el-e-1", "failure")]
    {
        let id = uuid();
        let response = server
            .put(
                &format!("/api/v1/trials/{id}"),
                token,
                &trial(&id, ADA_SWITCH, robot, "on", "push_top", outcome),
                None,
            )
            .await;
        assert_eq!(response.status(), StatusCode::CREATED);
        ids.push(id);
    }
    let patched = server
        .request(Method::PATCH, &format!("/api/v1/trials/{}", ids[0]), Some(&server.admin))
        .header("content-type", "application/merge-patch+json")
        .body(r#"{"confirmed": false}"#)
        .send()
        .await
        .unwrap();
    assert_eq!(patched.status(), StatusCode::OK);
    assert_eq!(patched.json::<Value>().await.unwrap()["confirmed"], false);
    let bad = server
        .request(Method::PATCH, &format!("/api/v1/trials/{}", ids[0]), Some(&server.admin))
        .json(&json!({ "outcome": "success" }))
        .send()
        .await
        .unwrap();
    assert_eq!(pointers(&problem(bad, StatusCode::UNPROCESSABLE_ENTITY).await), vec!["/outcome"]);
    problem(
        server
            .request(Method::PATCH, &format!("/api/v1/trials/{}", ids[1]), Some(&a))
            .json(&json!({ "confirmed": true }))
            .send()
            .await
            .unwrap(),
        StatusCode::FORBIDDEN,
    )
    .await;

    let all = server.get_json("/api/v1/trials").await;
    assert_eq!(all["items"].as_array().unwrap().len(), 3);
    assert_eq!(all["items"][0]["confirmed"], false);
    let failures = server.get_json("/api/v1/trials?outcome=failure&robot=el-e-1").await;
    assert_eq!(failures["items"].as_array().unwrap().len(), 1);
    let own: Value = server.get("/api/v1/trials", &a).await.json().await.unwrap();
    assert_eq!(own["items"].as_array().unwrap().len(), 2, "a robot sees only its own trials");
    problem(server.get("/api/v1/trials?robot=el-e-2", &a).await, StatusCode::FORBIDDEN).await;
    problem(
        server.get("/api/v1/trials?since=yesterday", &server.admin).await,
        StatusCode::BAD_REQUEST,
    )
    .await;
    problem(server.get(&format!("/api/v1/trials/{}", ids[1]), &a).await, StatusCode::FORBIDDEN)
        .await;
}

#[tokio::test]
async fn a_trial_recorded_as_refuted_can_be_confirmed_later() {
    let server = TestServer::start().await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let id = uuid();
    let mut body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    body["confirmed"] = json!(false);
    let path = format!("/api/v1/trials/{id}");
    assert_eq!(server.put(&path, &robot, &body, None).await.status(), StatusCode::CREATED);
    for verdict in [true, false, true] {
        let patched = server
            .request(Method::PATCH, &path, Some(&server.admin))
            .json(&json!({ "confirmed": verdict }))
            .send()
            .await
            .unwrap();
        assert_eq!(patched.status(), StatusCode::OK, "confirmed {verdict}");
        assert_eq!(patched.json::<Value>().await.unwrap()["confirmed"], verdict);
    }
    // The robot's retry of its first submission is still the same trial.
    assert_eq!(server.put(&path, &robot, &body, None).await.status(), StatusCode::OK);
}

#[tokio::test]
async fn sixteen_robots_writing_a_thousand_trials_each_store_exactly_sixteen_thousand() {
    let server = TestServer::start().await;
    let mut robots = tokio::task::JoinSet::new();
    for n in 0..16 {
        let robot = format!("robot-{n}");
        let token = server.token(Role::Robot, &robot).await;
        let client = server.client.clone();
        let url = server.url.clone();
        robots.spawn(async move {
            for _ in 0..1000 {
                let id = uuid();
                let body = trial(&id, ADA_SWITCH, &robot, "on", "push_top", "success");
                let response = client
                    .put(format!("{url}/api/v1/trials/{id}"))
                    .bearer_auth(&token)
                    .json(&body)
                    .send()
                    .await
                    .unwrap();
                assert_eq!(response.status(), StatusCode::CREATED);
            }
        });
    }
    robots.join_all().await;
    let mut seen = std::collections::HashSet::new();
    let mut cursor = String::new();
    loop {
        let page = server.get_json(&format!("/api/v1/trials?limit=500{cursor}")).await;
        for item in page["items"].as_array().unwrap() {
            assert!(seen.insert(item["id"].as_str().unwrap().to_owned()), "no trial listed twice");
        }
        match page["next_cursor"].as_str() {
            Some(next) => cursor = format!("&cursor={next}"),
            None => break,
        }
    }
    assert_eq!(seen.len(), 16_000);
}

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
async fn the_same_trial_sent_many_times_at_once_is_stored_once() {
    let server = TestServer::start().await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let id = uuid();
    let body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    let mut racing = tokio::task::JoinSet::new();
    for n in 0..10 {
        let mut body = body.clone();
        if n == 9 {
            body["outcome"] = "failure".into();
        }
        let request =
            server.request(Method::PUT, &format!("/api/v1/trials/{id}"), Some(&robot)).json(&body);
        racing.spawn(async move { (n, request.send().await.unwrap().status()) });
    }
    let statuses = racing.join_all().await;
    let created: Vec<usize> =
        statuses.iter().filter(|(_, s)| *s == StatusCode::CREATED).map(|(n, _)| *n).collect();
    let [winner] = created[..] else { panic!("exactly one PUT creates: {statuses:?}") };
    // The stored body decides: the same body again is 200, a different one under its id 409.
    for &(n, status) in statuses.iter().filter(|(n, _)| *n != winner) {
        let same_as_stored = (n == 9) == (winner == 9);
        let expected = if same_as_stored { StatusCode::OK } else { StatusCode::CONFLICT };
        assert_eq!(status, expected, "PUT {n} after PUT {winner} created: {statuses:?}");
    }
    assert_eq!(server.get_json("/api/v1/trials").await["items"].as_array().unwrap().len(), 1);
}
