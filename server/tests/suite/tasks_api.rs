//! Tasks over HTTP (DESIGN §8): asking, listing, cancelling, claiming under a lease with long
//! polls, heartbeats and finishing with the holder's trial, and every refusal on the way.

use std::time::{Duration, Instant};

use pps_server::clock::ManualClock;
use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, Response, StatusCode};
use serde_json::{Value, json};

async fn claimed(server: &TestServer, token: &str, robot: &str) -> Value {
    let response = claim(server, token, robot, 0.0).await;
    assert_eq!(response.status(), StatusCode::OK, "{robot} got a task");
    response.json().await.unwrap()
}

async fn post(server: &TestServer, path: &str, token: &str, body: Option<Value>) -> Response {
    let mut request = server.request(Method::POST, path, Some(token));
    if let Some(body) = body {
        request = request.json(&body);
    }
    request.send().await.unwrap()
}

fn id(task: &Value) -> &str {
    task["id"].as_str().unwrap()
}

/// Records a trial of `robot` and returns its id.
async fn record(server: &TestServer, token: &str, robot: &str, epc: &str, action: &str) -> String {
    let id = uuid::Uuid::new_v4().to_string();
    let behavior = match (epc, action) {
        (FLIP_SWITCH, "on") => "flip_up",
        (FLIP_SWITCH, "off") => "flip_down",
        (ADA_SWITCH, "on") => "push_top",
        (ADA_SWITCH, "off") => "push_bottom",
        _ => "pull_chain",
    };
    let body = trial(&id, epc, robot, action, behavior, "success");
    let response = server.put(&format!("/api/v1/trials/{id}"), token, &body, None).await;
    assert_eq!(response.status(), StatusCode::CREATED, "{}", response.text().await.unwrap());
    id
}

/// A robot of `class` with every behaviour, and its token.
async fn robot(server: &TestServer, id: &str, class: &str) -> String {
    let all = ["light_switch", "pull_back", "push", "pull_lamp", "drop"];
    register_robot(server, id, class, &all, 40.0).await;
    server.token(Role::Robot, id).await
}

#[tokio::test]
async fn a_task_is_asked_for_listed_read_and_cancelled() {
    let server = TestServer::start().await;
    let response =
        ask(&server, json!({ "epc": FLIP_SWITCH, "action": "off", "note": "hallway" })).await;
    assert_eq!(response.status(), StatusCode::CREATED);
    let location = response.headers()["location"].to_str().unwrap().to_owned();
    let task: Value = response.json().await.unwrap();
    assert_eq!(location, format!("/api/v1/tasks/{}", id(&task)));
    assert_eq!(task["state"], "queued");
    assert_eq!(task["attempts"], 0);
    assert_eq!(task["note"], "hallway");
    assert_eq!(task["created_by"], "test admin");
    assert_eq!(server.get_json(&location).await, task);

    let other = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    let all = server.get_json("/api/v1/tasks").await;
    let ids: Vec<&str> = all["items"].as_array().unwrap().iter().map(id).collect();
    assert_eq!(ids, [id(&other), id(&task)], "newest first");
    let page = server.get_json("/api/v1/tasks?limit=1").await;
    assert_eq!(page["items"][0]["id"], other["id"]);
    let cursor = page["next_cursor"].as_str().unwrap();
    let next = server.get_json(&format!("/api/v1/tasks?limit=1&cursor={cursor}")).await;
    assert_eq!(next["items"][0]["id"], task["id"]);
    assert!(next["next_cursor"].is_null());
    let on_lamp = server.get_json(&format!("/api/v1/tasks?epc={LAMP}")).await;
    assert_eq!(on_lamp["items"].as_array().unwrap().len(), 1);

    let path = format!("/api/v1/tasks/{}/cancel", id(&task));
    let cancelled: Value = post(&server, &path, &server.admin, None).await.json().await.unwrap();
    assert_eq!(cancelled["state"], "cancelled");
    assert_eq!(cancelled["reason"], "cancelled by test admin");
    let again = post(&server, &path, &server.admin, None).await;
    assert_eq!(again.status(), StatusCode::OK, "cancelling twice is no error");
    let cancelled_list = server.get_json("/api/v1/tasks?state=cancelled").await;
    assert_eq!(cancelled_list["items"].as_array().unwrap().len(), 1);

    let unknown = format!("/api/v1/tasks/{}", uuid::Uuid::new_v4());
    problem(server.get(&unknown, &server.admin).await, StatusCode::NOT_FOUND).await;
    problem(server.get("/api/v1/tasks/not-a-uuid", &server.admin).await, StatusCode::BAD_REQUEST)
        .await;
    problem(server.get("/api/v1/tasks?state=asleep", &server.admin).await, StatusCode::BAD_REQUEST)
        .await;
    problem(server.get("/api/v1/tasks?limit=501", &server.admin).await, StatusCode::BAD_REQUEST)
        .await;
}

#[tokio::test]
async fn a_task_the_tag_or_its_targets_cannot_take_is_refused_with_a_pointer() {
    let server = TestServer::start().await;
    robot(&server, "el-e-1", "el-e").await;
    register_robot(&server, "weak-1", "weak", &["push"], 15.0).await;
    let cases = [
        (json!({ "epc": FLIP_SWITCH, "action": "dance" }), "/action", "offers off, on"),
        (json!({ "epc": "E2003412000000000000ABCD", "action": "on" }), "/epc", "register"),
        (json!({ "epc": "not hex", "action": "on" }), "/epc", "not an EPC"),
        (json!({ "epc": FLIP_SWITCH }), "/action", "required"),
        (json!({ "epc": FLIP_SWITCH, "action": "on", "robot": "ghost-1" }), "/robot", "registered"),
        (
            json!({ "epc": FLIP_SWITCH, "action": "on", "robot": "weak-1" }),
            "/robot",
            "light_switch",
        ),
        (
            json!({ "epc": FLIP_SWITCH, "action": "on", "class": "pr2" }),
            "/class",
            "no robot of class",
        ),
        (json!({ "epc": FLIP_SWITCH, "action": "on", "class": "weak" }), "/class", "cannot"),
        (
            json!({ "epc": FLIP_SWITCH, "action": "on", "robot": "el-e-1", "class": "stretch" }),
            "/class",
            "of class el-e",
        ),
        (json!({ "epc": FLIP_SWITCH, "action": "on", "priority": 1 }), "/priority", "no field"),
        (
            json!({ "epc": FLIP_SWITCH, "action": "on", "note": "x".repeat(501) }),
            "/note",
            "at most",
        ),
        (json!([]), "", "object"),
    ];
    for (body, pointer, words) in cases {
        let refused =
            problem(ask(&server, body.clone()).await, StatusCode::UNPROCESSABLE_ENTITY).await;
        assert!(pointers(&refused).contains(&pointer.to_owned()), "{body}: {refused}");
        assert!(refused.to_string().contains(words), "{body}: {refused}");
    }
    let archive =
        server.request(Method::DELETE, &format!("/api/v1/tags/{DRAWER}"), Some(&server.admin));
    assert_eq!(archive.header("if-match", "*").send().await.unwrap().status(), StatusCode::OK);
    let refused = problem(
        ask(&server, json!({ "epc": DRAWER, "action": "open" })).await,
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(refused.to_string().contains("archived"), "{refused}");
    let nothing = server.get_json("/api/v1/tasks").await;
    assert_eq!(nothing["items"], json!([]), "a refused task is not stored");
    let targeted =
        asked(&server, json!({ "epc": FLIP_SWITCH, "action": "on", "class": "el-e" })).await;
    assert_eq!(targeted["class"], "el-e");
}

#[tokio::test]
async fn a_waiting_robot_gets_a_new_task_at_once_and_an_empty_wait_ends_in_204() {
    let server = TestServer::start().await;
    let token = robot(&server, "el-e-1", "el-e").await;
    let started = Instant::now();
    let empty = claim(&server, &token, "el-e-1", 0.3).await;
    assert_eq!(empty.status(), StatusCode::NO_CONTENT);
    assert!(started.elapsed() >= Duration::from_millis(300), "it waited");

    let waiting = {
        let (url, token) = (server.url.clone(), token.clone());
        tokio::spawn(async move {
            let response = reqwest::Client::new()
                .post(format!("{url}/api/v1/robots/el-e-1/tasks/claim?wait=20"))
                .bearer_auth(token)
                .send()
                .await
                .unwrap();
            (Instant::now(), response.status(), response.json::<Value>().await.unwrap())
        })
    };
    robots_waiting(&server, 1).await;
    let task = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "off" })).await;
    let asked_at = Instant::now();
    let (answered_at, status, got) = waiting.await.unwrap();
    assert_eq!(status, StatusCode::OK);
    assert!(answered_at - asked_at < Duration::from_secs(2), "answered as the task came");
    assert_eq!(got["id"], task["id"]);
    assert_eq!(got["state"], "claimed");
    assert_eq!(got["claimed_by"], "el-e-1");
    assert_eq!(got["attempts"], 1);
    let lease = pps_server::clock::parse(got["lease_until"].as_str().unwrap()).unwrap();
    assert_eq!(lease, server.now() + server.config.lease, "a claim holds the task for the lease");

    problem(claim(&server, &token, "el-e-1", 31.0).await, StatusCode::BAD_REQUEST).await;
    problem(claim(&server, &token, "el-e-2", 0.0).await, StatusCode::FORBIDDEN).await;
    let answered = claim(&server, &token, "el-e-1", 0.0).await;
    assert_eq!(answered.status(), StatusCode::NO_CONTENT, "a claimed task is not offered again");
}

#[tokio::test]
async fn only_robots_that_can_run_the_action_and_are_targeted_are_offered_it() {
    let server = TestServer::start().await;
    register_robot(&server, "pusher-1", "el-e", &["push"], 15.0).await;
    let pusher = server.token(Role::Robot, "pusher-1").await;
    let stretch = robot(&server, "stretch-1", "stretch").await;
    let el_e = robot(&server, "el-e-1", "el-e").await;
    let rocker = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    let for_el_e = asked(&server, json!({ "epc": LAMP, "action": "on", "class": "el-e" })).await;

    let listed = server.get("/api/v1/tasks", &pusher).await.json::<Value>().await.unwrap();
    assert_eq!(listed["items"], json!([]), "the pusher may claim neither");
    let seen = server.get(&format!("/api/v1/tasks/{}", id(&rocker)), &pusher).await;
    problem(seen, StatusCode::FORBIDDEN).await;
    assert_eq!(claim(&server, &pusher, "pusher-1", 0.0).await.status(), StatusCode::NO_CONTENT);
    let listed = server.get("/api/v1/tasks", &stretch).await.json::<Value>().await.unwrap();
    assert_eq!(listed["items"].as_array().unwrap().len(), 1, "not the el-e one: {listed}");
    let got = claimed(&server, &stretch, "stretch-1").await;
    assert_eq!(got["id"], rocker["id"]);
    assert_eq!(claim(&server, &stretch, "stretch-1", 0.0).await.status(), StatusCode::NO_CONTENT);
    let got = claimed(&server, &el_e, "el-e-1").await;
    assert_eq!(got["id"], for_el_e["id"]);
    let forbidden = server.get("/api/v1/tasks?robot=el-e-1", &stretch).await;
    problem(forbidden, StatusCode::FORBIDDEN).await;
}

#[tokio::test]
async fn the_holder_heartbeats_and_finishes_with_its_own_trial() {
    let server = TestServer::start().await;
    let token = robot(&server, "el-e-1", "el-e").await;
    let other = robot(&server, "el-e-2", "el-e").await;
    let task = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "off" })).await;
    let held = claimed(&server, &token, "el-e-1").await;
    let heartbeat = format!("/api/v1/tasks/{}/heartbeat", id(&task));
    let finish = format!("/api/v1/tasks/{}/finish", id(&task));

    let beat: Value = post(&server, &heartbeat, &token, None).await.json().await.unwrap();
    assert!(beat["lease_until"].as_str() >= held["lease_until"].as_str(), "{beat}");
    problem(post(&server, &heartbeat, &other, None).await, StatusCode::FORBIDDEN).await;

    let missing = json!({ "trial": uuid::Uuid::new_v4(), "outcome": "success" });
    let refused = problem(
        post(&server, &finish, &token, Some(missing)).await,
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert_eq!(pointers(&refused), ["/trial"]);
    let theirs = record(&server, &other, "el-e-2", FLIP_SWITCH, "off").await;
    let body = json!({ "trial": theirs, "outcome": "success" });
    let refused =
        problem(post(&server, &finish, &token, Some(body)).await, StatusCode::FORBIDDEN).await;
    assert!(refused["detail"].as_str().unwrap().contains("el-e-2"), "{refused}");
    let wrong_action = record(&server, &token, "el-e-1", FLIP_SWITCH, "on").await;
    let body = json!({ "trial": wrong_action, "outcome": "success" });
    let refused =
        problem(post(&server, &finish, &token, Some(body)).await, StatusCode::UNPROCESSABLE_ENTITY)
            .await;
    assert_eq!(pointers(&refused), ["/trial"]);
    let mine = record(&server, &token, "el-e-1", FLIP_SWITCH, "off").await;
    let body = json!({ "trial": mine, "outcome": "failure" });
    let refused =
        problem(post(&server, &finish, &token, Some(body)).await, StatusCode::UNPROCESSABLE_ENTITY)
            .await;
    assert_eq!(pointers(&refused), ["/outcome"]);
    let body = json!({ "trial": "nope", "extra": 1 });
    let refused =
        problem(post(&server, &finish, &token, Some(body)).await, StatusCode::UNPROCESSABLE_ENTITY)
            .await;
    assert_eq!(pointers(&refused), ["/extra", "/trial", "/outcome"]);
    assert_eq!(server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await["state"], "claimed");

    let body = json!({ "trial": mine, "outcome": "success" });
    let done: Value =
        post(&server, &finish, &token, Some(body.clone())).await.json().await.unwrap();
    assert_eq!(done["state"], "done");
    assert_eq!(done["trial"], mine);
    assert_eq!(done["claimed_by"], "el-e-1");
    assert!(done["lease_until"].is_null());
    let repeated = post(&server, &finish, &token, Some(body)).await;
    assert_eq!(repeated.status(), StatusCode::OK, "a retried finish is answered again");
    let beat = problem(post(&server, &heartbeat, &token, None).await, StatusCode::CONFLICT).await;
    assert!(beat["detail"].as_str().unwrap().contains("done"), "{beat}");
    let cancel = format!("/api/v1/tasks/{}/cancel", id(&task));
    problem(post(&server, &cancel, &server.admin, None).await, StatusCode::CONFLICT).await;
    assert_eq!(server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await, done);
    let mine_listed = server.get("/api/v1/tasks", &token).await.json::<Value>().await.unwrap();
    assert_eq!(mine_listed["items"][0]["id"], task["id"], "a robot sees what it did");
}

#[tokio::test]
async fn a_lease_that_runs_out_requeues_the_task_and_the_third_fails_it() {
    let server = TestServer::start().await;
    let robots = [
        robot(&server, "el-e-1", "el-e").await,
        robot(&server, "el-e-2", "el-e").await,
        robot(&server, "el-e-3", "el-e").await,
    ];
    let mut feed = SseClient::connect(&server, &server.admin, None).await;
    let task = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    assert_eq!(feed.until("task_changed", "task", id(&task)).await.data["state"], "queued");
    for (n, token) in robots.iter().enumerate() {
        let name = format!("el-e-{}", n + 1);
        let response = claim(&server, token, &name, 5.0).await;
        assert_eq!(response.status(), StatusCode::OK, "attempt {}", n + 1);
        let held: Value = response.json().await.unwrap();
        assert_eq!(held["attempts"], n + 1);
        let event = feed.until("task_changed", "task", id(&task)).await;
        assert_eq!(
            (event.data["state"].as_str(), event.data["claimed_by"].as_str()),
            (Some("claimed"), Some(name.as_str()))
        );
        // The robot dies: no heartbeat. The lease runs out and the sweep acts on its own.
        server.advance(server.config.lease);
        let next = feed.until("task_changed", "task", id(&task)).await;
        let heartbeat = format!("/api/v1/tasks/{}/heartbeat", id(&task));
        let lost =
            problem(post(&server, &heartbeat, token, None).await, StatusCode::CONFLICT).await;
        assert!(lost["detail"].as_str().unwrap().contains("lost its lease"), "{lost}");
        if n < 2 {
            assert_eq!(next.data["state"], "queued");
        } else {
            assert_eq!(next.data["state"], "failed");
        }
    }
    let failed = server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await;
    assert_eq!(failed["state"], "failed");
    assert_eq!(failed["holders"], json!(["el-e-1", "el-e-2", "el-e-3"]));
    let reason = failed["reason"].as_str().unwrap();
    assert!(reason.contains("ran out 3 times") && reason.contains("el-e-2"), "{reason}");
    assert_eq!(claim(&server, &robots[0], "el-e-1", 0.0).await.status(), StatusCode::NO_CONTENT);
}

#[tokio::test]
async fn a_robot_whose_token_is_revoked_mid_task_loses_it_to_another() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", &["light_switch"], 15.0).await;
    let minted =
        pps_server::store::tokens::create(&server.db, Role::Robot, "el-e-1", None).await.unwrap();
    let other = robot(&server, "el-e-2", "el-e").await;
    let task = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    claimed(&server, &minted.token, "el-e-1").await;
    assert!(pps_server::store::tokens::revoke(&server.db, &minted.record.id).await.unwrap());
    let heartbeat = format!("/api/v1/tasks/{}/heartbeat", id(&task));
    // Revoked in the store as another process would: the cache trusts the token a little longer.
    server.advance(pps_server::auth::TOKEN_RECHECK_AFTER);
    let refused = post(&server, &heartbeat, &minted.token, None).await;
    problem(refused, StatusCode::UNAUTHORIZED).await;
    let response = claim(&server, &other, "el-e-2", 0.0).await;
    assert_eq!(response.status(), StatusCode::NO_CONTENT, "not before its lease ran out");
    server.advance(server.config.lease);
    let response = claim(&server, &other, "el-e-2", 10.0).await;
    assert_eq!(response.status(), StatusCode::OK);
    let taken: Value = response.json().await.unwrap();
    assert_eq!(taken["id"], task["id"]);
    assert_eq!(taken["attempts"], 2);
    let trial = record(&server, &other, "el-e-2", FLIP_SWITCH, "on").await;
    let finish = format!("/api/v1/tasks/{}/finish", id(&task));
    let body = json!({ "trial": trial, "outcome": "success" });
    let done: Value = post(&server, &finish, &other, Some(body)).await.json().await.unwrap();
    assert_eq!(done["state"], "done");
    assert_eq!(done["holders"], json!(["el-e-1", "el-e-2"]));
}

#[tokio::test]
async fn tasks_follow_a_retagged_tag_and_end_with_an_archived_one() {
    let server = TestServer::start().await;
    let token = robot(&server, "el-e-1", "el-e").await;
    let task = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    let new_epc = "E2003412000000000000BEEF";
    let retag = format!("/api/v1/tags/{LAMP}/retag");
    let retagged = post(&server, &retag, &server.admin, Some(json!({ "new_epc": new_epc }))).await;
    assert_eq!(retagged.status(), StatusCode::OK);
    let moved = server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await;
    assert_eq!(moved["epc"], new_epc);
    let refused = problem(
        ask(&server, json!({ "epc": LAMP, "action": "on" })).await,
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(refused.to_string().contains(new_epc), "names the successor: {refused}");
    let held = claimed(&server, &token, "el-e-1").await;
    assert_eq!(held["epc"], new_epc);

    let queued = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    let archive =
        server.request(Method::DELETE, &format!("/api/v1/tags/{FLIP_SWITCH}"), Some(&server.admin));
    assert_eq!(archive.header("if-match", "*").send().await.unwrap().status(), StatusCode::OK);
    let ended = server.get_json(&format!("/api/v1/tasks/{}", id(&queued))).await;
    assert_eq!(ended["state"], "cancelled");
    assert!(ended["reason"].as_str().unwrap().contains("archived"));
}

/// A registry on `path` in a runtime of its own, so stopping it stops its lease sweep too.
fn registry_in_own_runtime(
    path: std::path::PathBuf,
    clock: &ManualClock,
    lease: Duration,
) -> (String, tokio::sync::oneshot::Sender<()>, std::thread::JoinHandle<()>) {
    let clock = clock.clone();
    let (url_sender, url) = std::sync::mpsc::channel();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let thread = std::thread::spawn(move || {
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
        runtime.block_on(async move {
            let db = pps_server::Db::open_file(&path).await.unwrap();
            let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
            url_sender.send(format!("http://{}", listener.local_addr().unwrap())).unwrap();
            let state = pps_server::AppState::on_clock(db, clock.into()).with_task_lease(lease);
            let stopped = async move {
                let _ = stopped.await;
            };
            pps_server::serve(listener, state, stopped).await.unwrap();
        });
    });
    (url.recv().unwrap(), stop, thread)
}

#[tokio::test]
async fn queued_and_claimed_tasks_and_their_leases_survive_a_restart() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pps.db");
    let db = pps_server::Db::open_file(&path).await.unwrap();
    pps_server::tags::seed::seed_if_empty(&db).await.unwrap();
    let mint = |role, name: &'static str| {
        let db = db.clone();
        async move { pps_server::store::tokens::create(&db, role, name, None).await.unwrap().token }
    };
    let (admin, first, second) = (
        mint(Role::Admin, "admin").await,
        mint(Role::Robot, "el-e-1").await,
        mint(Role::Robot, "el-e-2").await,
    );
    let client = reqwest::Client::new();
    let send = |url: &str, path: &str, token: &str, body: Option<Value>| {
        let mut request = client.post(format!("{url}{path}")).bearer_auth(token);
        if let Some(body) = body {
            request = request.json(&body);
        }
        request.send()
    };
    let lease = Duration::from_secs(30);
    let clock = ManualClock::default();
    let (url, stop, thread) = registry_in_own_runtime(path.clone(), &clock, lease);
    for robot in ["el-e-1", "el-e-2"] {
        let body = json!({ "class": "el-e", "name": robot, "capabilities": ["light_switch", "pull_lamp"] });
        let put =
            client.put(format!("{url}/api/v1/robots/{robot}")).bearer_auth(&admin).json(&body);
        assert!(put.send().await.unwrap().status().is_success());
    }
    let held: Value =
        send(&url, "/api/v1/tasks", &admin, Some(json!({ "epc": FLIP_SWITCH, "action": "on" })))
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
    let claim_path =
        |robot: &str, wait: u32| format!("/api/v1/robots/{robot}/tasks/claim?wait={wait}");
    let got: Value =
        send(&url, &claim_path("el-e-1", 0), &first, None).await.unwrap().json().await.unwrap();
    assert_eq!(got["id"], held["id"]);
    let queued: Value =
        send(&url, "/api/v1/tasks", &admin, Some(json!({ "epc": LAMP, "action": "on" })))
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
    stop.send(()).unwrap();
    thread.join().unwrap();

    let (url, _stop, _thread) = registry_in_own_runtime(path, &clock, lease);
    let got: Value =
        send(&url, &claim_path("el-e-2", 0), &second, None).await.unwrap().json().await.unwrap();
    assert_eq!(got["id"], queued["id"], "the queued one survived; the held one is not offered yet");
    clock.advance(lease - Duration::from_secs(1));
    let early = send(&url, &claim_path("el-e-2", 0), &second, None).await.unwrap();
    assert_eq!(early.status(), StatusCode::NO_CONTENT, "not before the stored expiry");
    clock.advance(Duration::from_secs(1));
    let response = send(&url, &claim_path("el-e-2", 10), &second, None).await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    let taken: Value = response.json().await.unwrap();
    assert_eq!(taken["id"], held["id"], "the lease ran out on the restarted registry");
    assert_eq!(taken["attempts"], 2);
}

#[tokio::test]
async fn a_robot_of_a_reliable_class_is_preferred_then_the_one_that_asked_first() {
    let server = TestServer::start().await;
    let early = robot(&server, "el-e-1", "el-e").await;
    let late = robot(&server, "el-e-2", "el-e").await;
    let reliable = robot(&server, "stretch-1", "stretch").await;
    let mut tx = server.db.begin_write().await.unwrap();
    pps_server::store::learning::store_reliability(
        &mut tx,
        &pps_schema::Epc::parse(FLIP_SWITCH).unwrap(),
        "off",
        Some("stretch"),
        true,
    )
    .await
    .unwrap();
    tx.commit().await.unwrap();

    let wait = |token: String, robot: &'static str| {
        let url = server.url.clone();
        tokio::spawn(async move {
            let response = reqwest::Client::new()
                .post(format!("{url}/api/v1/robots/{robot}/tasks/claim?wait=20"))
                .bearer_auth(token)
                .send()
                .await
                .unwrap();
            response.json::<Value>().await.unwrap()
        })
    };
    let first_in_line = wait(early.clone(), "el-e-1");
    robots_waiting(&server, 1).await;
    let second_in_line = wait(late, "el-e-2");
    robots_waiting(&server, 2).await;
    let last_in_line = wait(reliable, "stretch-1");
    robots_waiting(&server, 3).await;
    let off = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "off" })).await;
    assert_eq!(last_in_line.await.unwrap()["id"], off["id"], "the reliable class first");
    let on = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "on" })).await;
    assert_eq!(first_in_line.await.unwrap()["id"], on["id"], "then the first to ask");
    let lamp = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    assert_eq!(second_in_line.await.unwrap()["id"], lamp["id"]);
}

#[tokio::test]
async fn sixteen_robots_doing_two_hundred_tasks_claim_each_exactly_once() {
    let server = TestServer::start().await;
    let mut tokens = Vec::new();
    for n in 0..16 {
        let class = if n % 2 == 0 { "el-e" } else { "stretch" };
        tokens.push((format!("robot-{n}"), robot(&server, &format!("robot-{n}"), class).await));
    }
    let mut asked_for = std::collections::BTreeSet::new();
    for n in 0..200 {
        let (epc, action) = [(FLIP_SWITCH, "on"), (LAMP, "off"), (ADA_SWITCH, "off")][n % 3];
        asked_for.insert(
            asked(&server, json!({ "epc": epc, "action": action })).await["id"]
                .as_str()
                .unwrap()
                .to_owned(),
        );
    }
    let workers: Vec<_> = tokens
        .into_iter()
        .map(|(robot, token)| {
            let url = server.url.clone();
            tokio::spawn(async move {
                let client = reqwest::Client::new();
                let mut got = Vec::new();
                loop {
                    let response = client
                        .post(format!("{url}/api/v1/robots/{robot}/tasks/claim"))
                        .bearer_auth(&token)
                        .send()
                        .await
                        .unwrap();
                    let task: Value = match response.status() {
                        StatusCode::OK => response.json().await.unwrap(),
                        StatusCode::NO_CONTENT => return got,
                        other => panic!("{robot}: {other}"),
                    };
                    assert_eq!(task["claimed_by"], robot.as_str());
                    let id = task["id"].as_str().unwrap().to_owned();
                    // Done at once: a robot holds only a few tasks at a time.
                    let trial_id = uuid::Uuid::new_v4().to_string();
                    let (epc, action) = (task["epc"].as_str().unwrap(), task["action"].as_str());
                    let behavior = match action {
                        Some("on") => "flip_up",
                        _ if epc == LAMP => "pull_chain",
                        _ => "push_bottom",
                    };
                    let body = trial(&trial_id, epc, &robot, action.unwrap(), behavior, "success");
                    let put =
                        client.put(format!("{url}/api/v1/trials/{trial_id}")).bearer_auth(&token);
                    assert_eq!(put.json(&body).send().await.unwrap().status(), StatusCode::CREATED);
                    let finish = client
                        .post(format!("{url}/api/v1/tasks/{id}/finish"))
                        .bearer_auth(&token)
                        .json(&json!({ "trial": trial_id, "outcome": "success" }));
                    assert_eq!(finish.send().await.unwrap().status(), StatusCode::OK);
                    got.push(id);
                }
            })
        })
        .collect();
    let mut claimed_ids = Vec::new();
    let mut busy = 0;
    for worker in workers {
        let got = worker.await.unwrap();
        busy += usize::from(!got.is_empty());
        claimed_ids.extend(got);
    }
    assert_eq!(claimed_ids.len(), 200, "every task claimed once, none twice");
    let distinct: std::collections::BTreeSet<String> = claimed_ids.into_iter().collect();
    assert_eq!(distinct, asked_for, "none lost");
    assert!(busy > 1, "the work was shared");
    let done = server.get_json("/api/v1/tasks?state=done&limit=500").await;
    assert_eq!(done["items"].as_array().unwrap().len(), 200);
}

/// The reason a robot gives that has no device with the tag.
const NOT_IN_ITS_ROOM: &str = "no device in its room has this tag";

async fn declined(server: &TestServer, token: &str, task: &Value, reason: &str) -> Response {
    let path = format!("/api/v1/tasks/{}/decline", id(task));
    post(server, &path, token, Some(json!({ "reason": reason }))).await
}

#[tokio::test]
async fn a_declined_task_goes_to_the_others_and_never_back_to_the_robot_that_declined() {
    let server = TestServer::start().await;
    let stretch = robot(&server, "stretch-1", "stretch").await;
    let el_e = robot(&server, "el-e-1", "el-e").await;
    let task = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    let held = claimed(&server, &stretch, "stretch-1").await;
    assert_eq!(held["id"], task["id"]);

    let taken =
        problem(declined(&server, &el_e, &task, NOT_IN_ITS_ROOM).await, StatusCode::CONFLICT);
    assert!(taken.await["detail"].as_str().unwrap().contains("stretch-1 holds"));
    for bad in [json!({}), json!({ "reason": " " }), json!({ "reason": "a\nb" })] {
        let path = format!("/api/v1/tasks/{}/decline", id(&task));
        let refused = problem(
            post(&server, &path, &stretch, Some(bad)).await,
            StatusCode::UNPROCESSABLE_ENTITY,
        )
        .await;
        assert_eq!(refused["errors"][0]["pointer"], "/reason", "{refused}");
    }
    let unchanged = server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await;
    assert_eq!(
        (unchanged["state"].as_str(), unchanged["claimed_by"].as_str()),
        (Some("claimed"), Some("stretch-1"))
    );

    let response = declined(&server, &stretch, &task, &format!("  {NOT_IN_ITS_ROOM} ")).await;
    assert_eq!(response.status(), StatusCode::OK);
    let back: Value = response.json().await.unwrap();
    assert_eq!(back["state"], "queued");
    assert_eq!(back["claimed_by"], Value::Null);
    assert_eq!(back["attempts"], 0, "a decline is not a lease run out: {back}");
    assert_eq!(back["declined"].as_array().unwrap().len(), 1, "{back}");
    assert_eq!(back["declined"][0]["robot"], "stretch-1");
    assert_eq!(back["declined"][0]["reason"], NOT_IN_ITS_ROOM);
    assert_eq!(back["declined"][0]["detail"], Value::Null, "it said nothing more: {back}");
    assert!(pps_server::clock::parse(back["declined"][0]["at"].as_str().unwrap()).is_some());
    let listed = server.get_json("/api/v1/tasks").await;
    assert_eq!(listed["items"][0]["declined"], back["declined"], "reads show the decline");

    assert_eq!(claim(&server, &stretch, "stretch-1", 0.0).await.status(), StatusCode::NO_CONTENT);
    let again: Value =
        declined(&server, &stretch, &task, "another reason").await.json().await.unwrap();
    assert_eq!(again["declined"], back["declined"], "declining twice changes nothing");
    let listed = server.get("/api/v1/tasks", &stretch).await.json::<Value>().await.unwrap();
    assert_eq!(listed["items"][0]["declined"], back["declined"], "it held it, so it sees it");
    let got = claimed(&server, &el_e, "el-e-1").await;
    assert_eq!(got["id"], task["id"], "el-e-1 is");
    assert_eq!(got["attempts"], 1);
}

#[tokio::test]
async fn a_decline_keeps_the_robots_own_words_apart_from_the_reason() {
    let server = TestServer::start().await;
    let stretch = robot(&server, "stretch-1", "stretch").await;
    let task = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    let path = format!("/api/v1/tasks/{}/decline", id(&task));
    let advice = "it tried and could not find the tag: move the red towel away from the tag";
    let said = "no tag taken near the pointed location: the red region is 35 cm across";

    for bad in
        [json!({ "reason": advice, "detail": "a\nb" }), json!({ "reason": advice, "detail": 3 })]
    {
        let refused = problem(
            post(&server, &path, &stretch, Some(bad)).await,
            StatusCode::UNPROCESSABLE_ENTITY,
        )
        .await;
        assert_eq!(refused["errors"][0]["pointer"], "/detail", "{refused}");
    }
    let unchanged = server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await;
    assert_eq!(unchanged["declined"], json!([]), "a refused decline changes nothing");

    let body = json!({ "reason": advice, "detail": said });
    let back: Value = post(&server, &path, &stretch, Some(body)).await.json().await.unwrap();
    assert_eq!(back["declined"][0]["reason"], advice, "{back}");
    assert_eq!(back["declined"][0]["detail"], said, "{back}");
    assert_eq!(
        back["stuck"],
        format!("stretch-1 declined: {advice}; no other robot can do it"),
        "why it waits is said in the caretaker's words only"
    );
    let listed = server.get_json("/api/v1/tasks").await;
    assert_eq!(listed["items"][0]["declined"], back["declined"], "reads show it");
}

#[tokio::test]
async fn only_the_holder_or_a_robot_the_queued_task_is_meant_for_may_decline_it() {
    let server = TestServer::start().await;
    let stretch = robot(&server, "stretch-1", "stretch").await;
    let el_e = robot(&server, "el-e-1", "el-e").await;
    let for_el_e = asked(&server, json!({ "epc": LAMP, "action": "on", "robot": "el-e-1" })).await;
    let refused = problem(
        declined(&server, &stretch, &for_el_e, NOT_IN_ITS_ROOM).await,
        StatusCode::FORBIDDEN,
    )
    .await;
    assert!(
        refused["detail"].as_str().unwrap().contains("not meant for robot stretch-1"),
        "{refused}"
    );
    let before_claiming = declined(&server, &el_e, &for_el_e, NOT_IN_ITS_ROOM).await;
    assert_eq!(before_claiming.status(), StatusCode::OK, "queued and meant for el-e-1");

    let ended = asked(&server, json!({ "epc": LAMP, "action": "off" })).await;
    let path = format!("/api/v1/tasks/{}/cancel", id(&ended));
    assert_eq!(post(&server, &path, &server.admin, None).await.status(), StatusCode::OK);
    problem(declined(&server, &el_e, &ended, NOT_IN_ITS_ROOM).await, StatusCode::CONFLICT).await;
    let missing = json!({ "id": uuid::Uuid::new_v4() });
    problem(declined(&server, &el_e, &missing, NOT_IN_ITS_ROOM).await, StatusCode::NOT_FOUND).await;
    let by_a_person = declined(&server, &server.admin, &for_el_e, NOT_IN_ITS_ROOM).await;
    problem(by_a_person, StatusCode::FORBIDDEN).await;
}

#[tokio::test]
async fn when_every_robot_that_could_do_it_declined_the_task_says_so_at_once() {
    let server = TestServer::start().await;
    let stretch = robot(&server, "stretch-1", "stretch").await;
    register_robot(&server, "pusher-1", "el-e", &["push"], 15.0).await;
    let pusher = server.token(Role::Robot, "pusher-1").await;
    // Both robots are online: each has just asked for work.
    assert_eq!(claim(&server, &pusher, "pusher-1", 0.0).await.status(), StatusCode::NO_CONTENT);
    assert_eq!(claim(&server, &stretch, "stretch-1", 0.0).await.status(), StatusCode::NO_CONTENT);
    let task = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    assert_eq!(task["waiting_for"], json!(["stretch-1"]), "{task}");
    assert_eq!(task["stuck"], Value::Null);

    claimed(&server, &stretch, "stretch-1").await;
    let back: Value =
        declined(&server, &stretch, &task, NOT_IN_ITS_ROOM).await.json().await.unwrap();
    let truth = "stretch-1 declined: no device in its room has this tag; no other robot can do it";
    assert_eq!(back["stuck"], truth, "{back}");
    assert_eq!(back["waiting_for"], json!([]));
    let read = server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await;
    assert_eq!((read["state"].as_str(), read["stuck"].as_str()), (Some("queued"), Some(truth)));
}

#[tokio::test]
async fn a_task_no_online_robot_can_take_says_so_until_one_comes_online() {
    let server = TestServer::start().await;
    let el_e = robot(&server, "el-e-1", "el-e").await;
    register_robot(&server, "pusher-1", "el-e", &["push"], 15.0).await;
    let task = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    assert_eq!(
        task["stuck"],
        "no robot that can do it is online (seen in the last 60 seconds): el-e-1 has not been \
         seen yet",
        "{task}"
    );
    assert_eq!(task["waiting_for"], json!([]));

    assert_eq!(server.get("/api/v1/tasks", &el_e).await.status(), StatusCode::OK);
    let read = server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await;
    assert_eq!(read["waiting_for"], json!(["el-e-1"]), "{read}");
    assert_eq!(read["stuck"], Value::Null);

    let nobody = asked(&server, json!({ "epc": LAMP, "action": "on", "class": "el-e" })).await;
    let path = format!("/api/v1/tasks/{}/cancel", id(&task));
    assert_eq!(post(&server, &path, &server.admin, None).await.status(), StatusCode::OK);
    let cancelled = server.get_json(&format!("/api/v1/tasks/{}", id(&task))).await;
    assert_eq!(cancelled["stuck"], Value::Null, "only a queued task waits");
    assert_eq!(nobody["waiting_for"], json!(["el-e-1"]), "{nobody}");
}

#[tokio::test]
async fn a_robot_that_declined_and_waits_in_line_does_not_hold_the_task_up() {
    let server = TestServer::start().await;
    let stretch = robot(&server, "stretch-1", "stretch").await;
    let el_e = robot(&server, "el-e-1", "el-e").await;
    let task = asked(&server, json!({ "epc": LAMP, "action": "on" })).await;
    claimed(&server, &stretch, "stretch-1").await;
    assert_eq!(declined(&server, &stretch, &task, NOT_IN_ITS_ROOM).await.status(), StatusCode::OK);

    // stretch-1 asked first, so it ranks first in line; having declined, it must not count.
    let waiting = {
        let (url, token) = (server.url.clone(), stretch.clone());
        tokio::spawn(async move {
            let path = format!("{url}/api/v1/robots/stretch-1/tasks/claim?wait=30");
            reqwest::Client::new().post(path).bearer_auth(token).send().await.unwrap().status()
        })
    };
    robots_waiting(&server, 1).await;
    let got = claimed(&server, &el_e, "el-e-1").await;
    assert_eq!(got["id"], task["id"]);
    waiting.abort();
}

#[tokio::test]
async fn a_trial_finishes_one_task_and_a_replayed_finish_says_what_the_first_said() {
    let server = TestServer::start().await;
    let token = robot(&server, "el-e-1", "el-e").await;
    let first = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "off" })).await;
    claimed(&server, &token, "el-e-1").await;
    let trial = record(&server, &token, "el-e-1", FLIP_SWITCH, "off").await;
    let finish = format!("/api/v1/tasks/{}/finish", id(&first));
    let success = json!({ "trial": trial, "outcome": "success" });
    let done: Value =
        post(&server, &finish, &token, Some(success.clone())).await.json().await.unwrap();
    assert_eq!(done["state"], "done");

    let otherwise = json!({ "trial": trial, "outcome": "failure" });
    let refused =
        problem(post(&server, &finish, &token, Some(otherwise)).await, StatusCode::CONFLICT).await;
    let detail = refused["detail"].as_str().unwrap();
    assert!(detail.contains("the outcome success"), "{detail}");
    let replayed = post(&server, &finish, &token, Some(success.clone())).await;
    assert_eq!(replayed.status(), StatusCode::OK);
    assert_eq!(replayed.json::<Value>().await.unwrap(), done, "the same finish, the same answer");

    let second = asked(&server, json!({ "epc": FLIP_SWITCH, "action": "off" })).await;
    claimed(&server, &token, "el-e-1").await;
    let finish = format!("/api/v1/tasks/{}/finish", id(&second));
    let reused =
        problem(post(&server, &finish, &token, Some(success)).await, StatusCode::CONFLICT).await;
    let detail = reused["detail"].as_str().unwrap();
    assert!(detail.contains(&format!("finished task {} already", id(&first))), "{detail}");
    let still = server.get_json(&format!("/api/v1/tasks/{}", id(&second))).await;
    assert_eq!((still["state"].as_str(), still["trial"].as_str()), (Some("claimed"), None));
}
