//! The real `pps-server` binary on `127.0.0.1:0` with a fresh database, as an operator starts
//! it, plus the API calls tests make to set the scene.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};

use pps_server::transport::DEFAULT_HEADER_READ_TIMEOUT;
use reqwest::{Method, StatusCode};
use serde_json::Value;
use tempfile::TempDir;

use crate::wait::{self, wait_for};
use crate::workspace::workspace_bin;

/// What replicas log: where they serve and which of them runs the Home Assistant bridge, at
/// info; everything else only when it warns.
const REPLICA_LOG: &str = "warn,pps_server::cli=info,pps_server::home_assistant=info";

/// Reads the first-start banner: where the registry serves, and the admin token made.
fn read_banner(line: &str, url: &mut Option<String>, admin_token: &mut Option<String>) {
    if let Some(rest) = line.strip_prefix("PPS-tag registry at ") {
        *url = Some(rest.trim_end_matches('/').to_owned());
    } else if line.starts_with("pps_") {
        *admin_token = Some(line.to_owned());
    }
}

/// A running registry; stopped when dropped.
#[derive(Debug)]
pub struct Registry {
    child: Child,
    /// Base URL without a trailing slash, e.g. `http://127.0.0.1:41234`.
    pub url: String,
    /// The one-time admin token from the first-start banner.
    pub admin_token: String,
    db: PathBuf,
    /// The `serve` flags it started with, for a restart.
    flags: Vec<String>,
    http: reqwest::Client,
    /// What the server wrote to stderr after its banner (warnings and errors).
    log: Arc<Mutex<Vec<String>>>,
    _dir: TempDir,
}

impl Registry {
    /// Starts `pps-server serve` on a fresh database and reads its first-start banner.
    pub fn start() -> Self {
        Self::with_flags(&[])
    }

    /// [`Registry::start`] with extra `serve` flags.
    pub fn with_flags(flags: &[&str]) -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let db = dir.path().join("pps.db");
        Self::serve(dir, db, flags, &[])
    }

    /// [`Registry::with_flags`] with extra environment variables, such as `SSL_CERT_FILE` for
    /// the CAs "this system" trusts.
    pub fn with_flags_and_env(flags: &[&str], env: &[(&str, &str)]) -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let db = dir.path().join("pps.db");
        Self::serve(dir, db, flags, env)
    }

    /// Starts `pps-server serve` on a fresh database at `db`, in a directory the caller
    /// prepared (a small file system, say).
    pub fn on_database(db: &Path) -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        Self::serve(dir, db.to_owned(), &[], &[])
    }

    /// Starts `pps-server serve` with `flags` on a fresh database at `db`, or returns what it
    /// said when it refused to start (bad settings, say).
    pub fn try_on_database(db: &Path, flags: &[&str]) -> Result<Self, String> {
        Self::try_spawn(db, (flags, &[]), ("warn", true), read_banner)
    }

    /// Starts the first replica of a registry on a new, empty PostgreSQL database at `url`
    /// (the database is "a path" to the CLI calls as well: `--db` takes either).
    pub fn on_postgres(url: &str, flags: &[&str]) -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        Self::serve(dir, PathBuf::from(url), flags, &[])
    }

    /// Starts another replica on this registry's (PostgreSQL) database; it finds the admin
    /// credential made already, so it prints no banner, and says where it serves in its log.
    pub fn another_replica(&self, flags: &[&str]) -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let mut replica =
            Self::spawn(&self.db, (flags, &[]), (REPLICA_LOG, false), |line, url, _| {
                if let Some((_, at)) = line.split_once("serving the PPS-tag registry") {
                    let at = at.split_once("url=").map_or("", |(_, at)| at);
                    let at = at.split_whitespace().next().unwrap_or_default();
                    *url = Some(at.trim_end_matches('/').to_owned());
                }
            });
        replica.admin_token = self.admin_token.clone();
        replica._dir = dir;
        replica
    }

    fn serve(dir: TempDir, db: PathBuf, flags: &[&str], env: &[(&str, &str)]) -> Self {
        let log = if db.to_string_lossy().starts_with("postgres") { REPLICA_LOG } else { "warn" };
        let mut registry = Self::spawn(&db, (flags, env), (log, true), read_banner);
        registry._dir = dir;
        registry
    }

    /// Starts `pps-server serve` and reads its stderr with `read` until it knows the URL (and
    /// the admin token, when `read` finds one; `another_replica` sets it after).
    fn spawn(
        db: &Path,
        flags: (&[&str], &[(&str, &str)]),
        log: (&str, bool),
        read: impl Fn(&str, &mut Option<String>, &mut Option<String>),
    ) -> Self {
        Self::try_spawn(db, flags, log, read)
            .unwrap_or_else(|said| panic!("pps-server exited before it served, saying:\n{said}"))
    }

    /// [`Self::spawn`], or what the server said when it exited instead.
    fn try_spawn(
        db: &Path,
        (flags, env): (&[&str], &[(&str, &str)]),
        (log_filter, banner): (&str, bool),
        read: impl Fn(&str, &mut Option<String>, &mut Option<String>),
    ) -> Result<Self, String> {
        let mut child = Command::new(workspace_bin("pps-server"))
            .args(["serve", "--listen", "127.0.0.1:0", "--db"])
            .arg(db)
            .args(flags)
            .env("RUST_LOG", log_filter)
            .env("NO_COLOR", "1")
            .envs(env.iter().copied())
            .stdin(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("pps-server starts");
        let mut lines = BufReader::new(child.stderr.take().expect("piped stderr")).lines();
        let (mut url, mut admin_token) = (None, None);
        let log = Arc::new(Mutex::new(Vec::new()));
        loop {
            let Some(line) = lines.next() else {
                child.wait().expect("the exited server is reaped");
                let said = log.lock().unwrap_or_else(|e| e.into_inner()).join("\n");
                return Err(said);
            };
            let line = line.expect("pps-server's stderr is text");
            read(line.trim(), &mut url, &mut admin_token);
            log.lock().unwrap_or_else(|e| e.into_inner()).push(line);
            if url.is_some() && (admin_token.is_some() || !banner) {
                break;
            }
        }
        // Keep draining stderr so the server never blocks on a full pipe, keeping what it says.
        let kept = log.clone();
        std::thread::spawn(move || {
            for line in lines.map_while(Result::ok) {
                kept.lock().unwrap_or_else(|e| e.into_inner()).push(line);
            }
        });
        Ok(Self {
            child,
            url: url.expect("a URL"),
            admin_token: admin_token.unwrap_or_default(),
            db: db.to_owned(),
            flags: flags.iter().map(|flag| flag.to_string()).collect(),
            // The server closes a connection left idle for its header-read timeout. A test that
            // blocks its runtime for longer (waiting for a command line's output) never sees the
            // close, and its next request would go out on the closed connection: the client
            // drops idle connections well before the server would.
            http: reqwest::Client::builder()
                .pool_idle_timeout(DEFAULT_HEADER_READ_TIMEOUT / 3)
                .build()
                .expect("an HTTP client"),
            log,
            _dir: tempfile::tempdir().expect("a temporary directory"),
        })
    }

    /// Kills the server with SIGKILL, as a power cut would, and reaps it.
    pub fn kill(&mut self) {
        self.child.kill().expect("the server was running");
        self.child.wait().expect("the killed server is reaped");
    }

    /// Starts the killed server again on the same address and database; returns once it
    /// answers.
    pub async fn restart(&mut self) {
        let address = self.url.trim_start_matches("http://").to_owned();
        let mut child = Command::new(workspace_bin("pps-server"))
            .args(["serve", "--listen", &address, "--db"])
            .arg(&self.db)
            .args(&self.flags)
            .env("RUST_LOG", "warn")
            .env("NO_COLOR", "1")
            .stdin(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("pps-server starts again");
        let lines = BufReader::new(child.stderr.take().expect("piped stderr")).lines();
        let kept = self.log.clone();
        std::thread::spawn(move || {
            for line in lines.map_while(Result::ok) {
                kept.lock().unwrap_or_else(|e| e.into_inner()).push(line);
            }
        });
        self.child = child;
        let health = format!("{}/healthz", self.url);
        wait_for(wait::DEADLINE, "the restarted registry to answer", || async {
            self.http.get(&health).send().await.is_ok()
        })
        .await;
    }

    /// The server's process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// The database file.
    pub fn db_path(&self) -> &Path {
        &self.db
    }

    /// A memory figure of the server process from `/proc/PID/status`, in KiB: `VmRSS` (now)
    /// or `VmHWM` (the peak so far).
    pub fn memory_kib(&self, field: &str) -> u64 {
        memory_kib(self.pid(), field)
            .unwrap_or_else(|| panic!("the server's /proc status has no {field}"))
    }

    /// Whether the server logged a line containing `text` since it started.
    pub fn logged(&self, text: &str) -> bool {
        self.log.lock().unwrap_or_else(|e| e.into_inner()).iter().any(|line| line.contains(text))
    }

    /// Runs `pps-server ARGS --db DB` and returns its output.
    pub fn cli(&self, args: &[&str]) -> std::process::Output {
        Command::new(workspace_bin("pps-server"))
            .args(args)
            .arg("--db")
            .arg(&self.db)
            .output()
            .expect("pps-server runs")
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

    /// A request with a token (none when empty), for tests that look at headers too.
    pub fn request(&self, method: Method, path: &str, token: &str) -> reqwest::RequestBuilder {
        let request = self.http.request(method, format!("{}{path}", self.url));
        if token.is_empty() { request } else { request.bearer_auth(token) }
    }

    /// GET as the admin: the status, the content type and the bytes.
    pub async fn get_bytes(&self, path: &str) -> (StatusCode, String, Vec<u8>) {
        let response = self.request(Method::GET, path, &self.admin_token).send().await;
        let response = response.expect("the registry answers");
        let kind = response.headers().get(reqwest::header::CONTENT_TYPE);
        let kind = kind.and_then(|v| v.to_str().ok()).unwrap_or_default().to_owned();
        (response.status(), kind, response.bytes().await.expect("a whole body").to_vec())
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

/// A memory field of process `pid`'s `/proc` status (`VmRSS`, `VmHWM`, ...), in KiB; `None`
/// once the process is gone.
pub fn memory_kib(pid: u32, field: &str) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status
        .lines()
        .find_map(|line| line.strip_prefix(field)?.strip_prefix(':'))
        .and_then(|value| value.trim().trim_end_matches("kB").trim().parse().ok())
}
