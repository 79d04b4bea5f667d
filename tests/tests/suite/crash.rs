//! Crash durability: the real `pps-server` process is killed with SIGKILL while 16 robots write
//! trials. Every trial it acknowledged must be there exactly once after a restart, the database
//! must pass SQLite's integrity check, and the robots' outboxes must then deliver the rest, so
//! the final count is exact.

use std::collections::HashSet;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use pps_robot::registry::RegistryClient;
use pps_schema::{RobotId, Trial};
use pps_test_kit::{ADA_SWITCH, Registry, wait, wait_for};
use serde_json::{Value, json};
use tokio::sync::watch;

const ROBOTS: usize = 16;

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

/// One robot recording trials until told to stop; returns every id it recorded. Once the
/// registry is down it records no more than the one trial that shows its outbox keeps it.
async fn robot_at_work(
    client: RegistryClient,
    mut stop: watch::Receiver<bool>,
    acknowledged: Arc<AtomicUsize>,
) -> Vec<String> {
    let mut recorded = Vec::new();
    while !*stop.borrow() {
        let trial = trial(client.robot().as_str());
        recorded.push(trial.id.to_string());
        let report = client.record_trial(&trial).await.expect("the outbox stores the trial");
        acknowledged.fetch_add(report.uploaded + report.already_stored, Ordering::Relaxed);
        if report.remaining > 0 {
            // The registry is down: the trial waits in the outbox until the test is done.
            stop.wait_for(|stop| *stop).await.expect("the test holds the stop sender");
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
    let mut registry = Registry::start();
    let (url, admin) = (registry.url.clone(), registry.admin_token.clone());
    let mut robots = Vec::new();
    for n in 0..ROBOTS {
        let id = format!("robot-{n}");
        let token = registry.token("robot", &id);
        let state = dir.path().join(&id);
        robots
            .push(RegistryClient::new(&url, &token, RobotId::parse(&id).unwrap(), &state).unwrap());
    }

    let (stop, stopped) = watch::channel(false);
    let acknowledged = Arc::new(AtomicUsize::new(0));
    let mut work = tokio::task::JoinSet::new();
    for robot in &robots {
        work.spawn(robot_at_work(robot.clone(), stopped.clone(), acknowledged.clone()));
    }
    // Kill the registry in the middle of the load.
    wait_for(Duration::from_secs(60), "the robots to get 600 trials through", || async {
        acknowledged.load(Ordering::Relaxed) >= 600
    })
    .await;
    registry.kill();
    // The robots work on while it is down, until each has a trial waiting in its outbox.
    wait_for(wait::DEADLINE, "every robot to keep a trial in its outbox", || async {
        robots.iter().all(|robot| robot.outbox().len().unwrap() > 0)
    })
    .await;
    stop.send(true).unwrap();
    let recorded: Vec<String> = work.join_all().await.into_iter().flatten().collect();
    let waiting: HashSet<String> = robots.iter().flat_map(outbox_ids).collect();
    let acknowledged_ids: HashSet<String> =
        recorded.iter().filter(|id| !waiting.contains(*id)).cloned().collect();

    // The database after the crash: intact, and holding every acknowledged trial.
    let integrity: String = {
        let db = pps_server::Db::open_file(registry.db_path()).await.unwrap();
        let check =
            sqlx::query_scalar("pragma integrity_check").fetch_one(db.reader()).await.unwrap();
        db.close().await;
        check
    };
    assert_eq!(integrity, "ok");
    registry.restart().await;
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
