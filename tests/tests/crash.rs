//! Crash durability: the real `pps-server` process is killed with SIGKILL while 16 robots write
//! trials. Every trial it acknowledged must be there exactly once after a restart, the database
//! must pass SQLite's integrity check, and the robots' outboxes must then deliver the rest, so
//! the final count is exact.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use pps_robot::registry::RegistryClient;
use pps_schema::{RobotId, Trial};
use pps_tests::workspace_bin;
use serde_json::{Value, json};

const ROBOTS: usize = 16;
const ADA_SWITCH: &str = "355AB1C60000002000000001";

/// `pps-server serve` on a fixed port, so a restart keeps the robots' URL.
struct Server {
    child: Child,
}

impl Server {
    fn start(db: &Path, port: u16) -> Self {
        let child = Command::new(workspace_bin("pps-server"))
            .args(["serve", "--listen", &format!("127.0.0.1:{port}"), "--db"])
            .arg(db)
            .env("RUST_LOG", "warn")
            .stdin(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("pps-server starts");
        Self { child }
    }

    fn kill(&mut self) {
        let status =
            Command::new("kill").arg("-KILL").arg(self.child.id().to_string()).status().unwrap();
        assert!(status.success());
        self.child.wait().unwrap();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn cli(db: &Path, args: &[&str]) -> String {
    let output =
        Command::new(workspace_bin("pps-server")).args(args).arg("--db").arg(db).output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).unwrap().trim().to_owned()
}

async fn wait_until_up(url: &str) {
    let deadline = Instant::now() + Duration::from_secs(20);
    while reqwest::get(format!("{url}/healthz")).await.is_err() {
        assert!(Instant::now() < deadline, "the server came up");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

fn trial(robot: &str) -> Trial {
    serde_json::from_value(json!({
        "id": uuid::Uuid::new_v4(), "epc": ADA_SWITCH, "robot": robot, "action": "on",
        "behavior": "push_top", "started_at": "2026-11-22T10:00:00Z",
        "finished_at": "2026-11-22T10:00:12Z", "outcome": "success",
        "detector": { "brightness_change": -0.25 },
        "forces": [{ "t": 0.4, "finger": "left", "force": [0.2, 0.1, 3.1] }]
    }))
    .unwrap()
}

/// Every trial id the registry lists, with how often each appears.
async fn stored(url: &str, admin: &str) -> Vec<String> {
    let http = reqwest::Client::new();
    let mut ids = Vec::new();
    let mut cursor = String::new();
    loop {
        let page: Value = http
            .get(format!("{url}/api/v1/trials?limit=500{cursor}"))
            .bearer_auth(admin)
            .send()
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
        ids.extend(
            page["items"].as_array().unwrap().iter().map(|t| t["id"].as_str().unwrap().to_owned()),
        );
        match page["next_cursor"].as_str() {
            Some(next) => cursor = format!("&cursor={next}"),
            None => return ids,
        }
    }
}

/// One robot recording trials until told to stop; returns every id it recorded.
async fn robot_at_work(
    client: RegistryClient,
    stop: Arc<AtomicBool>,
    acknowledged: Arc<AtomicUsize>,
) -> Vec<String> {
    let mut recorded = Vec::new();
    while !stop.load(Ordering::Acquire) {
        let trial = trial(client.robot().as_str());
        recorded.push(trial.id.to_string());
        let report = client.record_trial(&trial).await.expect("the outbox stores the trial");
        acknowledged.fetch_add(report.uploaded + report.already_stored, Ordering::Relaxed);
        if report.remaining > 0 {
            // The registry is down: the robot keeps working, its trials wait in the outbox.
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    }
    recorded
}

fn outbox_ids(client: &RegistryClient) -> HashSet<String> {
    client.outbox().pending().unwrap().into_iter().map(|p| p.trial.id.to_string()).collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_killed_registry_loses_no_acknowledged_trial_and_outboxes_deliver_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let db: PathBuf = dir.path().join("pps.db");
    cli(&db, &["migrate"]);
    let admin = cli(&db, &["token", "create", "--role", "admin", "--name", "crash test"]);
    let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let url = format!("http://127.0.0.1:{port}");
    let mut robots = Vec::new();
    for n in 0..ROBOTS {
        let id = format!("robot-{n}");
        let token = cli(&db, &["token", "create", "--role", "robot", "--name", &id]);
        let state = dir.path().join(&id);
        robots
            .push(RegistryClient::new(&url, &token, RobotId::parse(&id).unwrap(), &state).unwrap());
    }

    let mut server = Server::start(&db, port);
    wait_until_up(&url).await;
    let stop = Arc::new(AtomicBool::new(false));
    let acknowledged = Arc::new(AtomicUsize::new(0));
    let mut work = tokio::task::JoinSet::new();
    for robot in &robots {
        work.spawn(robot_at_work(robot.clone(), stop.clone(), acknowledged.clone()));
    }
    // Kill the registry in the middle of the load.
    let deadline = Instant::now() + Duration::from_secs(60);
    while acknowledged.load(Ordering::Relaxed) < 600 {
        assert!(Instant::now() < deadline, "the robots got trials through");
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    server.kill();
    // The robots work on while it is down.
    tokio::time::sleep(Duration::from_millis(300)).await;
    stop.store(true, Ordering::Release);
    let recorded: Vec<String> = work.join_all().await.into_iter().flatten().collect();
    let waiting: HashSet<String> = robots.iter().flat_map(outbox_ids).collect();
    let acknowledged_ids: HashSet<String> =
        recorded.iter().filter(|id| !waiting.contains(*id)).cloned().collect();

    // The database after the crash: intact, and holding every acknowledged trial.
    let integrity: String = {
        let db = pps_server::Db::open_file(&db).await.unwrap();
        let check =
            sqlx::query_scalar("pragma integrity_check").fetch_one(db.reader()).await.unwrap();
        db.close().await;
        check
    };
    assert_eq!(integrity, "ok");
    let _restarted = Server::start(&db, port);
    wait_until_up(&url).await;
    let after_crash = stored(&url, &admin).await;
    let unique: HashSet<&String> = after_crash.iter().collect();
    assert_eq!(unique.len(), after_crash.len(), "no trial stored twice");
    let missing: Vec<&String> = acknowledged_ids.iter().filter(|id| !unique.contains(id)).collect();
    assert!(missing.is_empty(), "{} acknowledged trials lost: {missing:?}", missing.len());
    eprintln!(
        "crash: {} trials recorded, {} acknowledged before the kill, {} found after the restart, {} waiting in outboxes",
        recorded.len(),
        acknowledged_ids.len(),
        after_crash.len(),
        waiting.len()
    );

    // The outboxes deliver the rest: the final count is exact.
    for robot in &robots {
        let report = robot.flush().await.unwrap();
        assert_eq!((report.remaining, report.rejected), (0, 0));
    }
    let mut everything = stored(&url, &admin).await;
    everything.sort();
    let mut expected = recorded.clone();
    expected.sort();
    assert_eq!(everything.len(), expected.len());
    assert_eq!(everything, expected, "every recorded trial stored exactly once");
}
