//! The real `pps-server` binary on `127.0.0.1:0` with a fresh database, as an operator starts
//! it, plus the API calls tests make to set the scene.

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use reqwest::{Method, StatusCode};
use serde_json::Value;
use tempfile::TempDir;

use crate::workspace_bin;

/// A running registry; stopped when dropped.
#[derive(Debug)]
pub struct Registry {
    child: Child,
    /// Base URL without a trailing slash, e.g. `http://127.0.0.1:41234`.
    pub url: String,
    /// The one-time admin token from the first-start banner.
    pub admin_token: String,
    db: PathBuf,
    http: reqwest::Client,
    _dir: TempDir,
}

impl Registry {
    /// Starts `pps-server serve` on a fresh database and reads its first-start banner.
    pub fn start() -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let db = dir.path().join("pps.db");
        let mut child = Command::new(workspace_bin("pps-server"))
            .args(["serve", "--listen", "127.0.0.1:0", "--db"])
            .arg(&db)
            .env("RUST_LOG", "warn")
            .stdin(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("pps-server starts");
        let mut lines = BufReader::new(child.stderr.take().expect("piped stderr")).lines();
        let (mut url, mut admin_token) = (None, None);
        while url.is_none() || admin_token.is_none() {
            let line = lines
                .next()
                .expect("pps-server printed its first-start banner before exiting")
                .expect("pps-server's stderr is text");
            let line = line.trim();
            if let Some(rest) = line.strip_prefix("PPS-tag registry at ") {
                url = Some(rest.trim_end_matches('/').to_owned());
            } else if line.starts_with("pps_") {
                admin_token = Some(line.to_owned());
            }
        }
        // Keep draining stderr so the server never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        Self {
            child,
            url: url.expect("a URL"),
            admin_token: admin_token.expect("an admin token"),
            db,
            http: reqwest::Client::new(),
            _dir: dir,
        }
    }

    /// Makes a login with `pps-server user add NAME --role ROLE --password-stdin`.
    pub fn add_user(&self, name: &str, role: &str, password: &str) {
        let mut child = Command::new(workspace_bin("pps-server"))
            .args(["user", "add", name, "--role", role, "--password-stdin", "--db"])
            .arg(&self.db)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("pps-server user add starts");
        writeln!(child.stdin.take().expect("piped stdin"), "{password}").expect("password written");
        let output = child.wait_with_output().expect("pps-server user add finishes");
        assert!(
            output.status.success(),
            "user add failed: {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }

    /// Mints a token with `pps-server token create` and returns it.
    pub fn token(&self, role: &str, name: &str) -> String {
        let output = Command::new(workspace_bin("pps-server"))
            .args(["token", "create", "--role", role, "--name", name, "--db"])
            .arg(&self.db)
            .output()
            .expect("pps-server token create runs");
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        String::from_utf8(output.stdout).expect("a token is text").trim().to_owned()
    }

    /// Calls the API with a token; returns the status and the JSON body (null when none).
    pub async fn call(
        &self,
        method: Method,
        path: &str,
        token: &str,
        body: Option<&Value>,
        headers: &[(&str, &str)],
    ) -> (StatusCode, Value) {
        let mut request =
            self.http.request(method, format!("{}{path}", self.url)).bearer_auth(token);
        if let Some(body) = body {
            request = request.json(body);
        }
        for (name, value) in headers {
            request = request.header(*name, *value);
        }
        let response = request.send().await.expect("the registry answers");
        let status = response.status();
        (status, response.json().await.unwrap_or(Value::Null))
    }

    /// GET as the admin, expecting 200.
    pub async fn get(&self, path: &str) -> Value {
        let (status, body) = self.call(Method::GET, path, &self.admin_token, None, &[]).await;
        assert_eq!(status, StatusCode::OK, "GET {path}: {body}");
        body
    }
}

impl Drop for Registry {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
