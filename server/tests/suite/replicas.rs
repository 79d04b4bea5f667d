//! Two `pps-server` processes on one PostgreSQL database behave as one registry (DESIGN §9):
//! one seed and one first admin however they start, ETags and idempotent trials decided by the
//! database, one change feed, revocation everywhere, and no acknowledged trial lost when a
//! replica is killed under load. Needs the cluster the test command starts
//! (`PPS_TEST_POSTGRES`).
//!
//! Long because every test starts two replicas on a fresh database; they are one test binary
//! so the test command can run them alone, against its cluster.

use std::collections::HashSet;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use pps_server::Db;
use pps_server::store::db::Location;
use pps_test_kit::{ADA_SWITCH, SseClient, robots_waiting, trial, uuid, wait_for};
use reqwest::StatusCode;
use serde_json::{Value, json};

const BIN: &str = env!("CARGO_BIN_EXE_pps-server");

/// One `pps-server serve` process.
struct Replica {
    child: Child,
    url: String,
    /// The admin token its first-start banner printed, if it printed one.
    first_admin: Option<String>,
}

impl Replica {
    /// Starts a replica on `db` without waiting for it.
    fn spawn(db: &str) -> Child {
        Command::new(BIN)
            .args(["serve", "--listen", "127.0.0.1:0", "--db", db])
            .env("RUST_LOG", "info")
            .env("NO_COLOR", "1")
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    }

    /// Waits until `child` serves, reading its banner.
    fn ready(mut child: Child) -> Self {
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
        let (mut url, mut first_admin) = (None, None);
        while url.is_none() {
            let line = lines.next().expect("the replica started serving").unwrap();
            let line = line.trim();
            if line.starts_with("pps_") {
                first_admin = Some(line.to_owned());
            } else if line.contains("serving the PPS-tag registry") {
                let at = line.split_once("url=").expect("the serving line names the url").1;
                let at = at.split_whitespace().next().unwrap().trim_end_matches('/');
                url = Some(at.to_owned());
            }
        }
        // Keep draining stderr so the replica never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        Self { child, url: url.unwrap(), first_admin }
    }
}

impl Drop for Replica {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Two replicas started at the same moment on a new database, and its admin token.
async fn two_replicas() -> (Replica, Replica, String, Location) {
    let location = pps_test_kit::postgres::fresh_database().await;
    let Location::Postgres(url) = &location else { unreachable!() };
    let (a, b) = (Replica::spawn(url), Replica::spawn(url));
    let (a, b) = (Replica::ready(a), Replica::ready(b));
    let admins: Vec<&String> = a.first_admin.iter().chain(&b.first_admin).collect();
    assert_eq!(admins.len(), 1, "exactly one replica mints the first admin token");
    let admin = admins[0].clone();
    (a, b, admin, location)
}

async fn mint(
    client: &reqwest::Client,
    replica: &Replica,
    admin: &str,
    role: &str,
    name: &str,
) -> Value {
    let response = client
        .post(format!("{}/api/v1/tokens", replica.url))
        .bearer_auth(admin)
        .json(&json!({ "role": role, "name": name }))
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::CREATED);
    response.json().await.unwrap()
}

async fn put_trial(
    client: &reqwest::Client,
    url: &str,
    token: &str,
    body: &Value,
) -> reqwest::Result<StatusCode> {
    let id = body["id"].as_str().unwrap();
    let response = client
        .put(format!("{url}/api/v1/trials/{id}"))
        .bearer_auth(token)
        .json(body)
        .send()
        .await?;
    Ok(response.status())
}

async fn stored_trial_ids(location: &Location) -> Vec<String> {
    let db = Db::open(location).await.unwrap();
    let ids = sqlx::query_scalar("select id from trials order by seq")
        .fetch_all(db.reader())
        .await
        .unwrap();
    db.close().await;
    ids
}

#[tokio::test(flavor = "multi_thread")]
async fn replicas_starting_together_seed_once_and_mint_one_admin() {
    let (a, b, admin, location) = two_replicas().await;
    let client = reqwest::Client::new();
    for replica in [&a, &b] {
        let tags: Value = client
            .get(format!("{}/api/v1/tags", replica.url))
            .bearer_auth(&admin)
            .send()
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
        assert_eq!(tags["items"].as_array().unwrap().len(), 5, "the paper's five devices");
    }
    let db = Db::open(&location).await.unwrap();
    let (revisions, events): (i64, i64) = sqlx::query_as(
        "select (select count(*) from tag_revisions), \
                (select count(*) from events where kind = 'tag_changed')",
    )
    .fetch_one(db.reader())
    .await
    .unwrap();
    assert_eq!((revisions, events), (5, 5), "seeded once, not once per replica");
    db.close().await;
}

#[tokio::test(flavor = "multi_thread")]
async fn an_etag_from_one_replica_is_honoured_by_the_other() {
    let (a, b, admin, _) = two_replicas().await;
    let client = reqwest::Client::new();
    let path = format!("/api/v1/tags/{ADA_SWITCH}");
    let read = client.get(format!("{}{path}", a.url)).bearer_auth(&admin).send().await.unwrap();
    let etag = read.headers()["etag"].to_str().unwrap().to_owned();
    let mut entry: Value = read.json().await.unwrap();
    entry["properties"]["name"] = json!("hall light switch");
    let put = |url: String| {
        let (client, admin, etag, entry) = (&client, &admin, &etag, &entry);
        async move {
            client
                .put(url)
                .bearer_auth(admin)
                .header("if-match", etag)
                .json(entry)
                .send()
                .await
                .unwrap()
        }
    };
    let on_b = put(format!("{}{path}", b.url)).await;
    assert_eq!(on_b.status(), StatusCode::OK, "A's ETag is current on B");
    let on_a = put(format!("{}{path}", a.url)).await;
    assert_eq!(on_a.status(), StatusCode::PRECONDITION_FAILED, "B's write made it stale on A");
}

#[tokio::test(flavor = "multi_thread")]
async fn each_replicas_feed_carries_both_replicas_events_and_resumes_on_either() {
    let (a, b, admin, _) = two_replicas().await;
    let client = reqwest::Client::new();
    let robot =
        mint(&client, &a, &admin, "robot", "el-e-1").await["token"].as_str().unwrap().to_owned();
    let mut on_a = SseClient::open(&client, &a.url, &admin, None).await;
    let first = uuid();
    let body = trial(&first, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    assert_eq!(put_trial(&client, &b.url, &robot, &body).await.unwrap(), StatusCode::CREATED);
    let seen = on_a.until("trial_recorded", "trial", &first).await;
    drop(on_a);

    let mut written = Vec::new();
    for _ in 0..3 {
        let id = uuid();
        let body = trial(&id, ADA_SWITCH, "el-e-1", "off", "push_bottom", "success");
        assert_eq!(put_trial(&client, &a.url, &robot, &body).await.unwrap(), StatusCode::CREATED);
        written.push(id);
    }
    let mut on_b = SseClient::open(&client, &b.url, &admin, Some(seen.id)).await;
    let mut resumed = Vec::new();
    let mut last = seen.id;
    while resumed.len() < written.len() {
        let event = on_b.next(Duration::from_secs(10)).await.expect("the missed events arrive");
        assert!(event.id > last, "one order of ids across replicas");
        last = event.id;
        if event.kind == "trial_recorded" {
            resumed.push(event.data["trial"].as_str().unwrap().to_owned());
        }
    }
    assert_eq!(resumed, written, "B resumes A's events after the id A's client saw, in order");
}

#[tokio::test(flavor = "multi_thread")]
async fn the_same_trial_sent_to_both_at_once_is_stored_once() {
    let (a, b, admin, location) = two_replicas().await;
    let client = reqwest::Client::new();
    let robot =
        mint(&client, &a, &admin, "robot", "el-e-1").await["token"].as_str().unwrap().to_owned();
    for _ in 0..20 {
        let id = uuid();
        let body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
        let (to_a, to_b) = tokio::join!(
            put_trial(&client, &a.url, &robot, &body),
            put_trial(&client, &b.url, &robot, &body)
        );
        let mut statuses = [to_a.unwrap(), to_b.unwrap()];
        statuses.sort();
        assert_eq!(
            statuses,
            [StatusCode::OK, StatusCode::CREATED],
            "one stored it, one saw a retry"
        );
    }
    assert_eq!(stored_trial_ids(&location).await.len(), 20);
}

#[tokio::test(flavor = "multi_thread")]
async fn a_token_revoked_on_one_replica_stops_on_the_other_within_seconds() {
    let (a, b, admin, _) = two_replicas().await;
    let client = reqwest::Client::new();
    let minted = mint(&client, &a, &admin, "caretaker", "night nurse").await;
    let token = minted["token"].as_str().unwrap();
    let tags = format!("{}/api/v1/tags", b.url);
    let status = |client: &reqwest::Client| {
        let (client, tags) = (client.clone(), tags.clone());
        async move { client.get(tags).bearer_auth(token).send().await.unwrap().status() }
    };
    assert_eq!(status(&client).await, StatusCode::OK, "B caches the working token");
    let revoked = client
        .delete(format!("{}/api/v1/tokens/{}", a.url, minted["id"].as_str().unwrap()))
        .bearer_auth(&admin)
        .send()
        .await
        .unwrap();
    assert_eq!(revoked.status(), StatusCode::OK);
    let started = Instant::now();
    wait_for(Duration::from_secs(5), "B to refuse the revoked token", || async {
        status(&client).await == StatusCode::UNAUTHORIZED
    })
    .await;
    eprintln!("revoked on A, refused on B after {:.2?}", started.elapsed());
}

#[tokio::test(flavor = "multi_thread")]
async fn sixteen_robots_writing_fifty_trials_each_over_both_replicas_store_exactly_800() {
    let (a, b, admin, location) = two_replicas().await;
    let client = reqwest::Client::new();
    let urls = [a.url.clone(), b.url.clone()];
    let mut robots = tokio::task::JoinSet::new();
    for n in 0..16 {
        let name = format!("robot-{n}");
        let token =
            mint(&client, &a, &admin, "robot", &name).await["token"].as_str().unwrap().to_owned();
        let (client, urls) = (client.clone(), urls.clone());
        robots.spawn(async move {
            let mut ids = Vec::new();
            for i in 0..50 {
                let id = uuid();
                let body = trial(&id, ADA_SWITCH, &name, "on", "push_top", "success");
                let status = put_trial(&client, &urls[(n + i) % 2], &token, &body).await.unwrap();
                assert_eq!(status, StatusCode::CREATED);
                ids.push(id);
            }
            ids
        });
    }
    let sent: HashSet<String> = robots.join_all().await.into_iter().flatten().collect();
    let stored = stored_trial_ids(&location).await;
    assert_eq!(stored.len(), 800);
    assert_eq!(stored.into_iter().collect::<HashSet<_>>(), sent);
}

#[tokio::test(flavor = "multi_thread")]
async fn a_replica_killed_under_load_loses_no_acknowledged_trial() {
    let (mut a, b, admin, location) = two_replicas().await;
    let client = reqwest::Client::new();
    let acknowledged = Arc::new(Mutex::new(HashSet::new()));
    let sent = Arc::new(Mutex::new(HashSet::new()));
    let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let mut robots = tokio::task::JoinSet::new();
    for n in 0..8 {
        let name = format!("robot-{n}");
        let token =
            mint(&client, &b, &admin, "robot", &name).await["token"].as_str().unwrap().to_owned();
        let urls = [a.url.clone(), b.url.clone()];
        let (client, acknowledged, sent, stop) =
            (client.clone(), acknowledged.clone(), sent.clone(), stop.clone());
        robots.spawn(async move {
            let mut i = 0;
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                let id = uuid();
                let body = trial(&id, ADA_SWITCH, &name, "on", "push_top", "success");
                sent.lock().unwrap().insert(id.clone());
                if let Ok(StatusCode::CREATED) =
                    put_trial(&client, &urls[i % 2], &token, &body).await
                {
                    acknowledged.lock().unwrap().insert(id);
                }
                i += 1;
            }
        });
    }
    let acknowledged_reach = |n: usize| {
        let acknowledged = acknowledged.clone();
        let reason = format!("{n} trials to be acknowledged");
        async move {
            let reached = || async { acknowledged.lock().unwrap().len() >= n };
            wait_for(Duration::from_secs(30), &reason, reached).await
        }
    };
    acknowledged_reach(200).await;
    a.child.kill().unwrap();
    a.child.wait().unwrap();
    let at_kill = acknowledged.lock().unwrap().len();
    acknowledged_reach(at_kill + 100).await;
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    robots.join_all().await;

    let stored: HashSet<String> = stored_trial_ids(&location).await.into_iter().collect();
    let acknowledged = acknowledged.lock().unwrap().clone();
    eprintln!(
        "{} acknowledged ({at_kill} when A was killed), {} stored, {} sent",
        acknowledged.len(),
        stored.len(),
        sent.lock().unwrap().len()
    );
    assert!(acknowledged.is_subset(&stored), "every acknowledged trial is stored");
    assert!(stored.is_subset(&sent.lock().unwrap()), "nothing stored that no robot sent");
}

#[tokio::test(flavor = "multi_thread")]
async fn backup_on_postgresql_points_to_pg_dump_and_touches_nothing() {
    let location = pps_test_kit::postgres::fresh_database().await;
    let Location::Postgres(url) = &location else { unreachable!() };
    let dir = tempfile::tempdir().unwrap();
    let to = dir.path().join("copy.db");
    let output = Command::new(BIN)
        .args(["backup", "--to", to.to_str().unwrap(), "--db", url])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(said.contains("pg_dump") && said.lines().count() <= 2, "{said}");
    assert!(!to.exists());
    let mut conn = <sqlx::PgConnection as sqlx::Connection>::connect(url).await.unwrap();
    let tables: i64 = sqlx::query_scalar(
        "select count(*) from information_schema.tables where table_schema = 'public'",
    )
    .fetch_one(&mut conn)
    .await
    .unwrap();
    assert_eq!(tables, 0, "refusing, it did not even migrate the database");
}

#[tokio::test(flavor = "multi_thread")]
async fn a_robot_waiting_on_one_replica_gets_a_task_asked_on_the_other_at_once() {
    let (a, b, admin, _) = two_replicas().await;
    let client = reqwest::Client::new();
    let robot = serde_json::json!({
        "id": "el-e-1", "class": "el-e", "name": "EL-E-1",
        "capabilities": ["light_switch", "pull_back", "push", "pull_lamp", "drop"],
        "limits": { "max_force": 40.0 }
    });
    let registered =
        client.put(format!("{}/api/v1/robots/el-e-1", a.url)).bearer_auth(&admin).json(&robot);
    assert!(registered.send().await.unwrap().status().is_success());
    let token =
        mint(&client, &a, &admin, "robot", "el-e-1").await["token"].as_str().unwrap().to_owned();
    let waiting = {
        let (client, url) = (client.clone(), b.url.clone());
        tokio::spawn(async move {
            let claim = format!("{url}/api/v1/robots/el-e-1/tasks/claim?wait=20");
            let response = client.post(claim).bearer_auth(token).send().await.unwrap();
            (Instant::now(), response.status(), response.json::<Value>().await.unwrap())
        })
    };
    // The robot is in line on B before the task is asked for on A.
    robots_waiting(&b.url, 1).await;
    let asked = Instant::now();
    let task = client
        .post(format!("{}/api/v1/tasks", a.url))
        .bearer_auth(&admin)
        .json(&json!({ "epc": ADA_SWITCH, "action": "on" }))
        .send()
        .await
        .unwrap();
    assert_eq!(task.status(), StatusCode::CREATED);
    let task: Value = task.json().await.unwrap();
    let (answered, status, claimed) = waiting.await.unwrap();
    assert_eq!(status, StatusCode::OK);
    assert_eq!(claimed["id"], task["id"]);
    let took = answered - asked;
    eprintln!("asked on A, handed out on B after {took:.2?}");
    assert!(took < Duration::from_secs(5), "B's robot waited {took:.2?}, not woken by A's task");
}
