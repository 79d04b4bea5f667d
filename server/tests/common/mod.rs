//! A real registry on `127.0.0.1:0` with a fresh database, for tests that speak HTTP.
//!
//! The suite runs on SQLite, or on PostgreSQL when `PPS_TEST_STORE=postgres` (the test command
//! runs it both ways): each test then gets a database of its own in the cluster
//! `PPS_TEST_POSTGRES` names. Tests of what only a file has (backups, the bytes on disk) ask
//! for SQLite by name.
#![allow(dead_code)] // each test binary uses its own part of the harness

mod clock;
pub mod postgres;

use std::path::PathBuf;

use pps_server::clock::ManualClock;
use pps_server::identity::Role;
use pps_server::store::db::Location;
use pps_server::store::tokens;
use pps_server::{AppState, Db};
use reqwest::{Method, RequestBuilder, Response, StatusCode};
use serde_json::Value;
use tempfile::TempDir;

pub const ADA_SWITCH: &str = "355AB1C60000002000000001";
pub const DRAWER: &str = "355AB1C60000004000000001";

pub struct TestServer {
    pub url: String,
    pub db: Db,
    /// The database, as `--db` takes it.
    pub location: Location,
    /// Where the SQLite file is or would be (tests of files use [`TestServer::start_sqlite`]).
    pub db_path: PathBuf,
    pub admin: String,
    /// How long a claim on a task lasts.
    pub lease: std::time::Duration,
    /// Pictures the registry keeps per tag.
    pub pictures_per_tag: u32,
    pub client: reqwest::Client,
    /// The registry's clock: [`TestServer::advance`] moves it instead of waiting.
    clock: ManualClock,
    _dir: TempDir,
}

impl TestServer {
    /// A seeded registry with one admin token.
    pub async fn start() -> Self {
        Self::start_with_lease(pps_server::robots::waiting_line::DEFAULT_LEASE).await
    }

    /// [`Self::start`] with claims on tasks lasting `lease`.
    pub async fn start_with_lease(lease: std::time::Duration) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let location = match store_under_test() {
            Store::Sqlite => Location::File(dir.path().join("pps.db")),
            Store::Postgres => postgres::fresh_database().await,
        };
        Self::start_on(dir, location, lease, pps_server::trials::picture::DEFAULT_PICTURES_PER_TAG)
            .await
    }

    /// [`Self::start`] keeping only the newest `pictures` pictures of each tag.
    pub async fn start_keeping_pictures(pictures: u32) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let location = match store_under_test() {
            Store::Sqlite => Location::File(dir.path().join("pps.db")),
            Store::Postgres => postgres::fresh_database().await,
        };
        Self::start_on(dir, location, pps_server::robots::waiting_line::DEFAULT_LEASE, pictures)
            .await
    }

    /// A seeded registry on a SQLite file, whichever store the suite runs on.
    pub async fn start_sqlite() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let location = Location::File(dir.path().join("pps.db"));
        let pictures = pps_server::trials::picture::DEFAULT_PICTURES_PER_TAG;
        Self::start_on(dir, location, pps_server::robots::waiting_line::DEFAULT_LEASE, pictures)
            .await
    }

    async fn start_on(
        dir: TempDir,
        location: Location,
        lease: std::time::Duration,
        pictures_per_tag: u32,
    ) -> Self {
        let db_path = dir.path().join("pps.db");
        let db = Db::open(&location).await.unwrap();
        pps_server::tags::seed::seed_if_empty(&db).await.unwrap();
        let admin = tokens::create(&db, Role::Admin, "test admin", None).await.unwrap().token;
        let clock = ManualClock::default();
        let (url, shutdown) = Self::serve(db.clone(), &clock, lease, pictures_per_tag).await;
        std::mem::forget(shutdown);
        let client = reqwest::Client::new();
        Self {
            url,
            db,
            location,
            db_path,
            admin,
            lease,
            pictures_per_tag,
            client,
            clock,
            _dir: dir,
        }
    }

    /// The database as the command line's `--db` takes it.
    pub fn db_arg(&self) -> String {
        self.location.as_db_arg()
    }

    /// Serves `db` on a new port until the returned sender is dropped.
    async fn serve(
        db: Db,
        clock: &ManualClock,
        lease: std::time::Duration,
        pictures_per_tag: u32,
    ) -> (String, tokio::sync::oneshot::Sender<()>) {
        if std::env::var_os("TEST_LOG").is_some() {
            pps_server::ops::telemetry::init();
        }
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let url = format!("http://{}", listener.local_addr().unwrap());
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let state = AppState::on_clock(db, clock.clone().into())
            .with_task_lease(lease)
            .with_pictures_per_tag(pictures_per_tag);
        tokio::spawn(pps_server::serve(listener, state, async move {
            let _ = stopped.await;
        }));
        (url, stop)
    }

    /// A second server on the same database file, as after a restart; stops when dropped.
    pub async fn restarted(&self) -> (String, tokio::sync::oneshot::Sender<()>) {
        let db = Db::open(&self.location).await.unwrap();
        Self::serve(db, &self.clock, self.lease, self.pictures_per_tag).await
    }

    /// Mints a token as the CLI would, straight into the database.
    pub async fn token(&self, role: Role, name: &str) -> String {
        tokens::create(&self.db, role, name, None).await.unwrap().token
    }

    pub fn request(&self, method: Method, path: &str, token: Option<&str>) -> RequestBuilder {
        let builder = self.client.request(method, format!("{}{path}", self.url));
        match token {
            Some(token) => builder.bearer_auth(token),
            None => builder,
        }
    }

    pub async fn get(&self, path: &str, token: &str) -> Response {
        self.request(Method::GET, path, Some(token)).send().await.unwrap()
    }

    pub async fn get_json(&self, path: &str) -> Value {
        let response = self.get(path, &self.admin).await;
        assert_eq!(response.status(), StatusCode::OK, "GET {path}");
        response.json().await.unwrap()
    }

    /// PUT a JSON body with an optional precondition header.
    pub async fn put(
        &self,
        path: &str,
        token: &str,
        body: &Value,
        condition: Option<(&str, &str)>,
    ) -> Response {
        let mut request = self.request(Method::PUT, path, Some(token)).json(body);
        if let Some((name, value)) = condition {
            request = request.header(name, value);
        }
        request.send().await.unwrap()
    }
}

/// The store the suite runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Store {
    Sqlite,
    Postgres,
}

/// `PPS_TEST_STORE`: `postgres`, or SQLite when unset.
pub fn store_under_test() -> Store {
    match std::env::var("PPS_TEST_STORE").as_deref() {
        Ok("postgres") => Store::Postgres,
        Ok("sqlite") | Err(_) => Store::Sqlite,
        Ok(other) => panic!("PPS_TEST_STORE is sqlite or postgres, not {other:?}"),
    }
}

/// Reads a problem+json answer, checking its media type and status field.
pub async fn problem(response: Response, status: StatusCode) -> Value {
    assert_eq!(response.status(), status);
    let media = response.headers()["content-type"].to_str().unwrap().to_owned();
    assert_eq!(media, "application/problem+json");
    let body: Value = response.json().await.unwrap();
    assert_eq!(body["status"], status.as_u16());
    assert!(body["detail"].as_str().is_some_and(|d| !d.is_empty()), "{body}");
    body
}

/// The JSON pointers a validation problem lists.
pub fn pointers(problem: &Value) -> Vec<String> {
    problem["errors"]
        .as_array()
        .map(|errors| errors.iter().map(|e| e["pointer"].as_str().unwrap().to_owned()).collect())
        .unwrap_or_default()
}

/// A new valid entry for `epc`, based on the seeded ADA switch.
pub fn new_entry(epc: &str, name: &str) -> Value {
    let mut entry: Value =
        serde_json::from_str(include_str!("../../../seed_tags/ada_light_switch.json")).unwrap();
    entry["epc"] = epc.into();
    entry["properties"]["name"] = name.into();
    entry
}

/// Registers a robot as an admin.
pub async fn register_robot(
    server: &TestServer,
    id: &str,
    class: &str,
    capabilities: &[&str],
    max_force: f64,
) {
    let robot = serde_json::json!({
        "id": id, "class": class, "name": id.to_uppercase(),
        "capabilities": capabilities, "limits": { "max_force": max_force }
    });
    let response = server.put(&format!("/api/v1/robots/{id}"), &server.admin, &robot, None).await;
    assert!(response.status().is_success(), "{}", response.text().await.unwrap());
}

/// A valid trial body.
pub fn trial(
    id: &str,
    epc: &str,
    robot: &str,
    action: &str,
    behavior: &str,
    outcome: &str,
) -> Value {
    serde_json::json!({
        "id": id, "epc": epc, "robot": robot, "action": action, "behavior": behavior,
        "started_at": "2026-11-22T10:00:00Z", "finished_at": "2026-11-22T10:00:30Z",
        "outcome": outcome, "confirmed": null, "detector": { "kind": "test" },
        "forces": [], "measurements": {}
    })
}

/// A Server-Sent Events client reading one response.
pub struct SseClient {
    pub response: Response,
    pub buffer: String,
}

/// One event as received.
#[derive(Debug, Clone, PartialEq)]
pub struct SseEvent {
    pub id: i64,
    pub kind: String,
    pub data: Value,
}

impl SseClient {
    pub async fn connect(server: &TestServer, token: &str, last_event_id: Option<i64>) -> Self {
        Self::open(&server.client, &server.url, token, last_event_id).await
    }

    /// The feed of the registry at `url` (any replica).
    pub async fn open(
        client: &reqwest::Client,
        url: &str,
        token: &str,
        last_event_id: Option<i64>,
    ) -> Self {
        let mut request = client.get(format!("{url}/api/v1/events")).bearer_auth(token);
        if let Some(id) = last_event_id {
            request = request.header("last-event-id", id.to_string());
        }
        let response = request.send().await.unwrap();
        assert_eq!(response.status(), StatusCode::OK);
        assert!(
            response.headers()["content-type"].to_str().unwrap().starts_with("text/event-stream")
        );
        Self { response, buffer: String::new() }
    }

    /// The next event (skipping heartbeats), or `None` if none arrives within `wait`.
    pub async fn next(&mut self, wait: std::time::Duration) -> Option<SseEvent> {
        let deadline = tokio::time::Instant::now() + wait;
        loop {
            if let Some(end) = self.buffer.find("\n\n") {
                let block: String = self.buffer.drain(..end + 2).collect();
                let (mut id, mut kind, mut data) = (None, String::new(), String::new());
                for line in block.lines() {
                    if let Some(v) = line.strip_prefix("id:") {
                        id = v.trim().parse().ok();
                    } else if let Some(v) = line.strip_prefix("event:") {
                        kind = v.trim().to_owned();
                    } else if let Some(v) = line.strip_prefix("data:") {
                        data.push_str(v.trim());
                    }
                }
                if let Some(id) = id {
                    return Some(SseEvent { id, kind, data: serde_json::from_str(&data).unwrap() });
                }
                continue;
            }
            let chunk =
                tokio::time::timeout_at(deadline, self.response.chunk()).await.ok()?.unwrap()?;
            self.buffer.push_str(&String::from_utf8_lossy(&chunk));
        }
    }

    /// Events until one of `kind` about `key` = `value` arrives.
    pub async fn until(&mut self, kind: &str, key: &str, value: &str) -> SseEvent {
        loop {
            let event =
                self.next(std::time::Duration::from_secs(10)).await.expect("the event arrived");
            if event.kind == kind && event.data[key] == value {
                return event;
            }
        }
    }
}

/// The API's route table, as every router of this build has it.
pub fn route_table(server: &TestServer) -> Vec<pps_server::RouteSpec> {
    pps_server::router_with_routes(AppState::new(server.db.clone())).1
}

/// Every behaviour a robot of the paper can run.
pub const ALL: &[&str] = &["light_switch", "pull_back", "push", "pull_lamp", "drop"];

/// A fresh trial id, as a robot chooses one.
pub fn uuid() -> String {
    uuid::Uuid::new_v4().to_string()
}
