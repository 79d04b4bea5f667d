//! What the interop tests start besides the registry (the test kit's): the `pps-ros2` node
//! and the Cyclone DDS peer; each stopped when dropped.

#![allow(dead_code)]

pub mod netns;

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::sync::{Arc, Mutex};

use std::time::Duration;

use pps_test_kit::Registry;
use pps_test_kit::wait::try_wait_until;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

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

/// How long the node may take to do what a test asks: it starts, syncs and retries over DDS.
pub const PATIENCE: Duration = Duration::from_secs(30);

/// The real registry with the robot `el-e-1` registered (it cannot pull a lamp's cord), and
/// that robot's token.
pub async fn registry() -> (Registry, String) {
    let registry = Registry::start();
    let robot = json!({"id": "el-e-1", "class": "el-e", "name": "EL-E",
        "capabilities": ["light_switch", "pull_back", "push", "drop"]});
    let path = "/api/v1/robots/el-e-1";
    let (status, body) =
        registry.call(Method::PUT, path, &registry.admin_token, Some(&robot), &[]).await;
    assert!(status.is_success(), "registering el-e-1: {status} {body}");
    let token = registry.token("robot", "el-e-1");
    (registry, token)
}

/// Waits until the trial `id` is stored, and returns it.
pub async fn stored_trial(registry: &Registry, id: &str, node: &RosNode) -> Value {
    let stored = try_wait_until(PATIENCE, || async {
        let path = format!("/api/v1/trials/{id}");
        let (status, body) =
            registry.call(Method::GET, &path, &registry.admin_token, None, &[]).await;
        (status == StatusCode::OK).then_some(body)
    });
    stored.await.unwrap_or_else(|| panic!("trial {id} not stored; node log:\n{}", node.log()))
}

/// Waits until the node has logged `text` `times` times.
pub async fn logged_times(node: &RosNode, text: &str, times: usize) {
    let said = try_wait_until(PATIENCE, || async {
        (node.log().matches(text).count() >= times).then_some(())
    });
    said.await.unwrap_or_else(|| panic!("never logged `{text}` {times} times:\n{}", node.log()));
}

/// The `pps-ros2` node, on loopback.
pub struct RosNode {
    child: Child,
    log: Arc<Mutex<Vec<String>>>,
}

impl RosNode {
    pub fn start(registry: &Registry, token: &str, state: &Path) -> Self {
        Self::start_with(registry, token, state, &[])
    }

    /// The node with more command-line arguments.
    pub fn start_with(registry: &Registry, token: &str, state: &Path, args: &[&str]) -> Self {
        let mut child = Command::new(env!("CARGO_BIN_EXE_pps-ros2"))
            .args(["--server", &registry.url, "--robot", "el-e-1", "--state"])
            .arg(state)
            .args(args)
            .env("PPS_TOKEN", token)
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
