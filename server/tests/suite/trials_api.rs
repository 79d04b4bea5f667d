//! Trials through HTTP: idempotent PUTs under the robot's own UUID, checks, verdicts given later,
//! list filters, and many robots writing at once.

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

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
    // A robot id no robot can have is a typo to point out, not an empty history.
    let typo = problem(
        server.get("/api/v1/trials?robot=El-E%201", &server.admin).await,
        StatusCode::BAD_REQUEST,
    )
    .await;
    assert!(typo["detail"].as_str().unwrap().contains("is not a robot id"), "{typo}");
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
