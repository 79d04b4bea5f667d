//! A real registry on `127.0.0.1:0` with a fresh database, served from the test's own runtime,
//! for tests that speak HTTP to it and read its store.
//!
//! The server's suite runs on SQLite, or on PostgreSQL when `PPS_TEST_STORE=postgres` (the test
//! command runs it both ways): each test then gets a database of its own in the cluster
//! `PPS_TEST_POSTGRES` names. Tests of what only a file has (backups, the bytes on disk) ask
//! for SQLite by name.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

use pps_server::clock::ManualClock;
use pps_server::identity::Role;
use pps_server::store::db::Location;
use pps_server::store::tokens;
use pps_server::transport::Transport;
use pps_server::{AppState, Db, ServeOptions};
use reqwest::{Method, RequestBuilder, Response, StatusCode};
use serde_json::Value;
use tempfile::TempDir;
use tokio::sync::oneshot;
use tokio::task::JoinHandle;

use crate::postgres;

/// How a test wants its registry: everything a start-up can vary, in one place.
#[derive(Debug, Clone)]
pub struct Config {
    /// The store: SQLite, or PostgreSQL, as `PPS_TEST_STORE` says by default.
    pub store: Store,
    /// How long a claim on a task lasts.
    pub lease: Duration,
    /// Pictures the registry keeps per tag.
    pub pictures_per_tag: u32,
    /// Connection limits and TLS.
    pub transport: Transport,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            store: store_under_test(),
            lease: pps_server::robots::waiting_line::DEFAULT_LEASE,
            pictures_per_tag: pps_server::trials::picture::DEFAULT_PICTURES_PER_TAG,
            transport: Transport::default(),
        }
    }
}

/// A seeded registry with one admin token, served until dropped or [`TestServer::stop`]ped.
#[derive(Debug)]
pub struct TestServer {
    pub url: String,
    pub address: SocketAddr,
    pub db: Db,
    /// The database, as `--db` takes it.
    pub location: Location,
    /// Where the SQLite file is or would be (tests of files use [`TestServer::start_sqlite`]).
    pub db_path: PathBuf,
    pub admin: String,
    pub config: Config,
    pub client: reqwest::Client,
    /// The registry's clock: [`TestServer::advance`] moves it instead of waiting.
    clock: ManualClock,
    serving: Option<Serving>,
    _dir: TempDir,
}

/// A running server: the sender that stops it, and the task that returns when it has.
type Serving = (oneshot::Sender<()>, JoinHandle<std::io::Result<()>>);

impl TestServer {
    /// A seeded registry with one admin token, on the store the suite runs on.
    pub async fn start() -> Self {
        Self::start_with(Config::default()).await
    }

    /// [`Self::start`] with claims on tasks lasting `lease`.
    pub async fn start_with_lease(lease: Duration) -> Self {
        Self::start_with(Config { lease, ..Config::default() }).await
    }

    /// [`Self::start`] keeping only the newest `pictures` pictures of each tag.
    pub async fn start_keeping_pictures(pictures: u32) -> Self {
        Self::start_with(Config { pictures_per_tag: pictures, ..Config::default() }).await
    }

    /// A seeded registry on a SQLite file, whichever store the suite runs on.
    pub async fn start_sqlite() -> Self {
        Self::start_with(Config { store: Store::Sqlite, ..Config::default() }).await
    }

    /// The one start-up: a fresh database as `config` says, seeded, with an admin token.
    pub async fn start_with(config: Config) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let db_path = dir.path().join("pps.db");
        let location = match config.store {
            Store::Sqlite => Location::File(db_path.clone()),
            Store::Postgres => postgres::fresh_database().await,
        };
        let db = Db::open(&location).await.unwrap();
        pps_server::tags::seed::seed_if_empty(&db).await.unwrap();
        let admin = tokens::create(&db, Role::Admin, "test admin", None).await.unwrap().token;
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let address = listener.local_addr().unwrap();
        let clock = ManualClock::default();
        let serving = Some(serve(listener, db.clone(), &clock, &config));
        let client = reqwest::Client::new();
        let scheme = if config.transport.tls.is_some() { "https" } else { "http" };
        let url = format!("{scheme}://{address}");
        Self {
            url,
            address,
            db,
            location,
            db_path,
            admin,
            config,
            client,
            clock,
            serving,
            _dir: dir,
        }
    }

    /// The database as the command line's `--db` takes it.
    pub fn db_arg(&self) -> String {
        self.location.as_db_arg()
    }

    /// Stops serving, as a shutdown does, once every connection has ended.
    pub async fn stop(&mut self) {
        let Some((stop, stopped)) = self.serving.take() else { return };
        let _ = stop.send(());
        let returned = stopped.await.expect("the server's task ends without panicking");
        returned.expect("the server shuts down cleanly");
    }

    /// Starts the stopped registry again, on the same address and database.
    pub async fn restart(&mut self) {
        assert!(self.serving.is_none(), "stop the registry before restarting it");
        let db = Db::open(&self.location).await.unwrap();
        let listener = tokio::net::TcpListener::bind(self.address).await.unwrap();
        self.serving = Some(serve(listener, db, &self.clock, &self.config));
    }

    /// A second server on the same database, as after a restart; stops when dropped.
    pub async fn restarted(&self) -> (String, oneshot::Sender<()>) {
        let db = Db::open(&self.location).await.unwrap();
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let url = format!("http://{}", listener.local_addr().unwrap());
        let (stop, _) = serve(listener, db, &self.clock, &self.config);
        (url, stop)
    }

    /// Moves the registry's clock forward by `by`, as if that much time had passed: leases,
    /// expiry, throttles and sessions run out when a test says, not while it waits.
    pub fn advance(&self, by: Duration) {
        self.clock.advance(by);
    }

    /// The registry's time now.
    pub fn now(&self) -> time::OffsetDateTime {
        self.clock.now()
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

    /// GET as the admin, expecting 200.
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

    /// Every trial the registry holds, with their forces.
    pub async fn trials(&self) -> Vec<Value> {
        let page = self.get_json("/api/v1/trials?include=forces&limit=500").await;
        page["items"].as_array().unwrap().clone()
    }

    /// A tag's success statistics, as the tag page asks for them (`include`: `experiment,test`).
    pub async fn stats(&self, epc: &str, include: Option<&str>) -> Value {
        let include = include.map(|purposes| format!("?include={purposes}")).unwrap_or_default();
        self.get_json(&format!("/api/v1/tags/{epc}/stats{include}")).await
    }

    /// The picture at `path` (a trial's `picture`), read as a caretaker's browser would.
    pub async fn picture(&self, path: &str) -> Vec<u8> {
        let response = self.get(path, &self.admin).await;
        assert_eq!(response.status(), StatusCode::OK, "GET {path}");
        assert_eq!(response.headers()["content-type"], "image/png");
        response.bytes().await.unwrap().to_vec()
    }

    /// Changes a tag's entry as a caretaker would: read it, edit it, save it over that revision.
    pub async fn edit_tag(&self, epc: &str, edit: impl FnOnce(&mut Value)) {
        let path = format!("/api/v1/tags/{epc}");
        let response = self.get(&path, &self.admin).await;
        let etag = response.headers()["etag"].to_str().unwrap().to_owned();
        let mut entry: Value = response.json().await.unwrap();
        edit(&mut entry);
        let saved = self.put(&path, &self.admin, &entry, Some(("if-match", &etag))).await;
        assert_eq!(saved.status(), StatusCode::OK, "{}", saved.text().await.unwrap());
    }

    /// Archives a tag as a caretaker would.
    pub async fn archive_tag(&self, epc: &str) {
        let path = format!("/api/v1/tags/{epc}");
        let response = self.get(&path, &self.admin).await;
        let etag = response.headers()["etag"].to_str().unwrap().to_owned();
        let archived =
            self.request(Method::DELETE, &path, Some(&self.admin)).header("if-match", etag);
        assert_eq!(archived.send().await.unwrap().status(), StatusCode::OK);
    }

    /// The API's route table, as every router of this build has it.
    pub fn route_table(&self) -> Vec<pps_server::RouteSpec> {
        pps_server::router_with_routes(AppState::new(self.db.clone())).1
    }
}

/// Serves `db` on `listener` as `config` says, until the returned sender fires or is dropped.
fn serve(
    listener: tokio::net::TcpListener,
    db: Db,
    clock: &ManualClock,
    config: &Config,
) -> Serving {
    if std::env::var_os("TEST_LOG").is_some() {
        pps_server::ops::telemetry::init();
    }
    let (stop, stopped) = oneshot::channel::<()>();
    let state = AppState::on_clock(db, clock.clone().into())
        .with_task_lease(config.lease)
        .with_pictures_per_tag(config.pictures_per_tag);
    let options = ServeOptions { transport: config.transport.clone(), ..ServeOptions::default() };
    let serving = tokio::spawn(pps_server::serve_with(listener, state, options, async move {
        let _ = stopped.await;
    }));
    (stop, serving)
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
