//! What the interop tests start: the real `pps-server`, the `pps-ros2` node, and the Cyclone
//! DDS peer; each stopped when dropped.

#![allow(dead_code)]

pub mod netns;

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::sync::{Arc, Mutex};

use serde_json::{Value, json};

/// A binary of the workspace, built beside the test binary (`cargo build --workspace --bins`).
pub fn workspace_bin(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary knows its path");
    let path = exe.ancestors().nth(2).expect("target/<profile>").join(name);
    assert!(
        path.is_file(),
        "{} is missing: build the binaries first (`cargo build --workspace --bins`, as tests/run does)",
        path.display()
    );
    path
}

/// Keeps reading a child's stderr so it never blocks, for the failure message.
fn drain(stderr: impl std::io::Read + Send + 'static) -> Arc<Mutex<Vec<String>>> {
    let log = Arc::new(Mutex::new(Vec::new()));
    let kept = log.clone();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            kept.lock().unwrap_or_else(|e| e.into_inner()).push(line);
        }
    });
    log
}

/// The real registry on a fresh database, with the robot `el-e-1` registered.
pub struct Server {
    child: Child,
    db: PathBuf,
    pub url: String,
    pub admin: String,
    pub robot_token: String,
}

impl Server {
    pub async fn start(dir: &Path) -> Self {
        let db = dir.join("pps.db");
        let mut child = Command::new(workspace_bin("pps-server"))
            .args(["serve", "--listen", "127.0.0.1:0", "--db"])
            .arg(&db)
            .env("RUST_LOG", "warn")
            .stdin(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("pps-server starts");
        let mut lines = BufReader::new(child.stderr.take().expect("piped")).lines();
        let (mut url, mut admin) = (None, None);
        while url.is_none() || admin.is_none() {
            let line = lines.next().expect("pps-server printed its banner").expect("text");
            let line = line.trim();
            if let Some(rest) = line.strip_prefix("PPS-tag registry at ") {
                url = Some(rest.trim_end_matches('/').to_owned());
            } else if line.starts_with("pps_") {
                admin = Some(line.to_owned());
            }
        }
        std::thread::spawn(move || lines.map_while(Result::ok).for_each(drop));
        let (url, admin) = (url.expect("a URL"), admin.expect("an admin token"));
        let robot = json!({"id": "el-e-1", "class": "el-e", "name": "EL-E",
            "capabilities": ["light_switch", "pull_back", "push", "drop"]});
        let answer = reqwest::Client::new()
            .put(format!("{url}/api/v1/robots/el-e-1"))
            .bearer_auth(&admin)
            .json(&robot)
            .send()
            .await
            .expect("the registry answers");
        assert!(answer.status().is_success(), "registering el-e-1: {}", answer.status());
        let minted = Command::new(workspace_bin("pps-server"))
            .args(["token", "create", "--role", "robot", "--name", "el-e-1", "--db"])
            .arg(&db)
            .output()
            .expect("pps-server token create runs");
        assert!(minted.status.success(), "{}", String::from_utf8_lossy(&minted.stderr));
        let robot_token = String::from_utf8_lossy(&minted.stdout).trim().to_owned();
        Self { child, db, url, admin, robot_token }
    }

    /// Stops the registry, as when its machine goes away.
    pub fn stop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// Starts the stopped registry again on the same address and database; returns once it
    /// answers.
    pub async fn restart(&mut self) {
        let address = self.url.trim_start_matches("http://").to_owned();
        self.child = Command::new(workspace_bin("pps-server"))
            .args(["serve", "--listen", &address, "--db"])
            .arg(&self.db)
            .env("RUST_LOG", "warn")
            .stdin(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("pps-server starts again");
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
        let http = reqwest::Client::new();
        while http.get(format!("{}/healthz", self.url)).send().await.is_err() {
            assert!(std::time::Instant::now() < deadline, "the registry did not come back");
            tokio::time::sleep(std::time::Duration::from_millis(20)).await;
        }
    }

    /// GET a path with the admin token: status and body.
    pub async fn get(&self, path: &str) -> (u16, Value) {
        let answer = reqwest::Client::new()
            .get(format!("{}{path}", self.url))
            .bearer_auth(&self.admin)
            .send()
            .await
            .expect("the registry answers");
        let status = answer.status().as_u16();
        (status, answer.json().await.unwrap_or(Value::Null))
    }

    /// GET a path with the admin token: status, content type and the bytes.
    pub async fn get_bytes(&self, path: &str) -> (u16, String, Vec<u8>) {
        let answer = reqwest::Client::new()
            .get(format!("{}{path}", self.url))
            .bearer_auth(&self.admin)
            .send()
            .await
            .expect("the registry answers");
        let status = answer.status().as_u16();
        let kind = answer
            .headers()
            .get(reqwest::header::CONTENT_TYPE)
            .and_then(|v| v.to_str().ok())
            .unwrap_or_default()
            .to_owned();
        (status, kind, answer.bytes().await.map(|b| b.to_vec()).unwrap_or_default())
    }

    /// Waits until the trial `id` is stored, and returns it.
    pub async fn stored_trial(&self, id: &str, node: &RosNode) -> Value {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
        loop {
            let (status, body) = self.get(&format!("/api/v1/trials/{id}")).await;
            if status == 200 {
                return body;
            }
            assert!(
                std::time::Instant::now() < deadline,
                "trial {id} not stored; node log:\n{}",
                node.log()
            );
            tokio::time::sleep(std::time::Duration::from_millis(50)).await;
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The `pps-ros2` node, on loopback.
pub struct RosNode {
    child: Child,
    log: Arc<Mutex<Vec<String>>>,
}

impl RosNode {
    pub fn start(server: &Server, state: &Path) -> Self {
        Self::start_with(server, state, &[])
    }

    /// The node with more command-line arguments.
    pub fn start_with(server: &Server, state: &Path, args: &[&str]) -> Self {
        let mut child = Command::new(env!("CARGO_BIN_EXE_pps-ros2"))
            .args(["--server", &server.url, "--robot", "el-e-1", "--state"])
            .arg(state)
            .args(args)
            .env("PPS_TOKEN", &server.robot_token)
            .env("PPS_DDS_INTERFACE", "127.0.0.1")
            .env("RUST_LOG", "info")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("pps-ros2 starts");
        let log = drain(child.stderr.take().expect("piped"));
        Self { child, log }
    }

    /// What the node logged so far.
    pub fn log(&self) -> String {
        self.log.lock().unwrap_or_else(|e| e.into_inner()).join("\n")
    }
}

impl Drop for RosNode {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The Cyclone DDS peer (`peer/peer.py`), steered one JSON command at a time.
pub struct Peer {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
    log: Arc<Mutex<Vec<String>>>,
}

fn python() -> PathBuf {
    if let Some(python) = std::env::var_os("CYCLONEDDS_PYTHON") {
        return python.into();
    }
    let venv =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/cyclonedds-venv/bin/python");
    assert!(
        venv.exists(),
        "cyclonedds is not installed: run tests/cyclonedds/install (tests/run does), or set \
         CYCLONEDDS_PYTHON to a Python that has cyclonedds"
    );
    venv
}

impl Peer {
    pub fn start() -> Self {
        let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/peer/peer.py");
        let mut child = Command::new(python())
            .arg(script)
            .env("CYCLONEDDS_URI", netns::CYCLONEDDS_LOOPBACK)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the peer starts");
        let stdin = child.stdin.take().expect("piped");
        let stdout = BufReader::new(child.stdout.take().expect("piped"));
        let log = drain(child.stderr.take().expect("piped"));
        let mut peer = Self { child, stdin, stdout, log };
        let ready = peer.answer();
        assert_eq!(ready["ready"], true, "the peer did not start: {ready}");
        peer
    }

    fn answer(&mut self) -> Value {
        let mut line = String::new();
        self.stdout.read_line(&mut line).expect("the peer answers");
        serde_json::from_str(&line).unwrap_or_else(|_| {
            panic!("the peer said `{line}`; its stderr:\n{}", self.log.lock().unwrap().join("\n"))
        })
    }

    /// One command and its answer.
    pub fn command(&mut self, command: Value) -> Value {
        writeln!(self.stdin, "{command}").expect("the peer is running");
        self.answer()
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
