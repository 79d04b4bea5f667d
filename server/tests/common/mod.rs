//! A real registry on `127.0.0.1:0` with a fresh database file, for tests that speak HTTP.
#![allow(dead_code)] // each test binary uses its own part of the harness

use std::path::PathBuf;

use pps_server::auth::Role;
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
    pub db_path: PathBuf,
    pub admin: String,
    pub client: reqwest::Client,
    _dir: TempDir,
}

impl TestServer {
    /// A seeded registry with one admin token.
    pub async fn start() -> Self {
        if std::env::var_os("TEST_LOG").is_some() {
            pps_server::telemetry::init();
        }
        let dir = tempfile::tempdir().unwrap();
        let db_path = dir.path().join("pps.db");
        let db = Db::open(&db_path).await.unwrap();
        pps_server::seed::seed_if_empty(&db).await.unwrap();
        let admin = tokens::create(&db, Role::Admin, "test admin", None).await.unwrap().token;
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let url = format!("http://{}", listener.local_addr().unwrap());
        let state = AppState::new(db.clone());
        tokio::spawn(pps_server::serve(listener, state, std::future::pending()));
        Self { url, db, db_path, admin, client: reqwest::Client::new(), _dir: dir }
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
