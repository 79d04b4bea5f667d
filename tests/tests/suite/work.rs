//! Two real `pps-robot work` processes of different classes working one queue of tasks on the
//! real `pps-server`: one robot is killed holding a task, its lease runs out and the other
//! robot does it; both share the rest; `--max-tasks`, `--idle-exit` and SIGTERM end them. A
//! task on a tag no device of the simulated room has is declined at once, with the reason.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use pps_test_kit::fixtures::{self, ADA_SWITCH};
use pps_test_kit::{Registry, robots_waiting, wait, workspace_bin};
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

const LAMP: &str = "355AB1C60000003000000001";
const FLIP_SWITCH: &str = "355AB1C60000001000000001";
/// Short, so the dead robot's task comes back within the test's patience.
const LEASE_SECONDS: &str = "2";

/// A `pps-robot work` process and the lines it printed on stdout.
struct Worker {
    child: Child,
    said: Arc<Mutex<Vec<String>>>,
    _state: tempfile::TempDir,
}

impl Worker {
    fn start(registry: &Registry, robot: &str, token: &str, flags: &[&str]) -> Self {
        let state = tempfile::tempdir().unwrap();
        let mut child = Command::new(workspace_bin("pps-robot"))
            .args(["work", "--server", &registry.url, "--robot", robot, "--state"])
            .arg(state.path())
            .args(flags)
            .env("PPS_TOKEN", token)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("pps-robot work starts");
        let said = Arc::new(Mutex::new(Vec::new()));
        let lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let kept = said.clone();
        std::thread::spawn(move || {
            for line in lines.map_while(Result::ok) {
                kept.lock().unwrap().push(line);
            }
        });
        Self { child, said, _state: state }
    }

    fn signal(&self, name: &str) {
        let status = Command::new("kill")
            .arg(format!("-{name}"))
            .arg(self.child.id().to_string())
            .status()
            .unwrap();
        assert!(status.success());
    }

    /// Waits for the process to end by itself; its exit status.
    async fn exited(&mut self, what: &str) -> std::process::ExitStatus {
        wait::until(what, || {
            let status = self.child.try_wait().unwrap();
            async move { status }
        })
        .await
    }

    fn said(&self) -> Vec<String> {
        self.said.lock().unwrap().clone()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

async fn ask(registry: &Registry, epc: &str, action: &str) -> String {
    let body = json!({ "epc": epc, "action": action });
    let (status, task) =
        registry.call(Method::POST, "/api/v1/tasks", &registry.admin_token, Some(&body), &[]).await;
    assert_eq!(status, StatusCode::CREATED, "{task}");
    task["id"].as_str().unwrap().to_owned()
}

async fn task(registry: &Registry, id: &str) -> Value {
    registry.get(&format!("/api/v1/tasks/{id}")).await
}

/// The trial that finished `task`.
async fn trial_of(registry: &Registry, task: &Value) -> Value {
    let id = task["trial"].as_str().unwrap_or_else(|| panic!("no trial finished {task}"));
    registry.get(&format!("/api/v1/trials/{id}")).await
}

/// Waits until the task is in `state`; the task then.
async fn task_in(registry: &Registry, id: &str, state: &str) -> Value {
    wait::until(&format!("task {id} to be {state}"), || async move {
        let task = task(registry, id).await;
        (task["state"] == state).then_some(task)
    })
    .await
}

#[tokio::test]
async fn two_robots_share_a_queue_and_a_dead_robots_task_goes_to_the_other() {
    let registry = Registry::with_flags(&["--task-lease", LEASE_SECONDS]);
    let el_e = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let stretch = fixtures::robot(&registry, "stretch-1", "stretch").await;

    // The el-e waits for work and freezes; the task it is handed dies with it.
    let mut doomed = Worker::start(&registry, "el-e-1", &el_e, &[]);
    robots_waiting(&registry, 1).await;
    doomed.signal("STOP");
    let orphan = ask(&registry, ADA_SWITCH, "off").await;
    let held = task_in(&registry, &orphan, "claimed").await;
    assert_eq!(held["claimed_by"], "el-e-1");
    doomed.signal("KILL");
    doomed.exited("the killed robot to be gone").await;
    let killed_at = Instant::now();

    let mut survivor =
        Worker::start(&registry, "stretch-1", &stretch, &["--seed", "3", "--idle-exit", "60"]);
    let done = task_in(&registry, &orphan, "done").await;
    assert!(killed_at.elapsed() >= Duration::from_secs(1), "not before the lease ran out");
    assert_eq!(done["claimed_by"], "stretch-1");
    assert_eq!(done["holders"], json!(["el-e-1", "stretch-1"]));
    assert_eq!(done["attempts"], 2);
    let trial = trial_of(&registry, &done).await;
    assert_eq!(trial["robot"], "stretch-1");
    assert_eq!(trial["action"], "off");
    assert_eq!(trial["measurements"]["task"], orphan.as_str());

    // A fresh el-e joins: with both waiting, a burst of tasks goes to both.
    let mut one_task = Worker::start(&registry, "el-e-1", &el_e, &["--max-tasks", "1"]);
    robots_waiting(&registry, 2).await;
    let burst = [
        ask(&registry, LAMP, "on").await,
        ask(&registry, FLIP_SWITCH, "on").await,
        ask(&registry, LAMP, "off").await,
    ];
    let mut doers = std::collections::BTreeSet::new();
    let registry = &registry;
    for id in &burst {
        let ended = wait::until(&format!("task {id} to end"), || async move {
            let task = task(registry, id).await;
            (task["state"] != "queued" && task["state"] != "claimed").then_some(task)
        })
        .await;
        assert!(ended["trial"].is_string(), "{ended}");
        doers.insert(ended["claimed_by"].as_str().unwrap().to_owned());
    }
    assert_eq!(doers.into_iter().collect::<Vec<_>>(), ["el-e-1", "stretch-1"]);
    assert!(one_task.exited("--max-tasks 1 to end the el-e").await.success());
    assert_eq!(one_task.said().len(), 1, "{:?}", one_task.said());

    // SIGTERM while a task is under way: it is finished first.
    let last = ask(registry, FLIP_SWITCH, "off").await;
    task_in(registry, &last, "claimed").await;
    survivor.signal("TERM");
    assert!(survivor.exited("the stretch to stop after SIGTERM").await.success());
    let last = task(registry, &last).await;
    // Finished with the trial it made: done if the detector saw it work, failed if not.
    let trial = trial_of(registry, &last).await;
    let finished_as = if trial["outcome"] == "success" { "done" } else { "failed" };
    assert_eq!(last["state"], finished_as, "{last} after {trial}");
    assert!(survivor.said().iter().any(|line| line.contains(last["id"].as_str().unwrap())));
}

#[tokio::test]
async fn an_idle_robot_ends_by_itself() {
    let registry = Registry::start();
    let token = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let started = Instant::now();
    let mut idle = Worker::start(&registry, "el-e-1", &token, &["--idle-exit", "0.5"]);
    assert!(idle.exited("--idle-exit to end the robot").await.success());
    assert!(started.elapsed() >= Duration::from_millis(500));
    assert!(idle.said().is_empty());
}

#[tokio::test]
async fn a_robot_declines_a_tag_not_in_its_room_at_once_and_the_task_says_why() {
    let registry = Registry::start();
    let token = fixtures::robot(&registry, "stretch-1", "stretch").await;
    let bedside = "E2003412000000000000BED1";
    fixtures::copy_tag(&registry, LAMP, bedside, "Bedside lamp").await;
    let mut worker = Worker::start(&registry, "stretch-1", &token, &["--idle-exit", "60"]);
    robots_waiting(&registry, 1).await;

    let asked_at = Instant::now();
    let elsewhere = ask(&registry, bedside, "off").await;
    let registry = &registry;
    let declined = wait::until("the robot to decline", || async {
        let task = task(registry, &elsewhere).await;
        (!task["declined"].as_array().unwrap().is_empty()).then_some(task)
    })
    .await;
    let took = asked_at.elapsed();
    let reason = "no device in its simulated room has this tag";
    assert_eq!(declined["declined"][0]["robot"], "stretch-1");
    assert_eq!(declined["declined"][0]["reason"], reason);
    assert_eq!(declined["state"], "queued", "a robot that can may still take it");
    assert_eq!(
        declined["stuck"],
        format!("stretch-1 declined: {reason}; no other robot can do it").as_str()
    );
    assert!(took < Duration::from_secs(5), "declined in {took:?}, not after a lease");
    let said = worker.said();
    assert!(
        said.iter().any(|line| line.contains(&elsewhere) && line.ends_with(reason)),
        "{said:?}"
    );

    // It goes on working: a task in its room is done.
    let here = ask(registry, LAMP, "off").await;
    let done = task_in(registry, &here, "done").await;
    assert_eq!(done["claimed_by"], "stretch-1");
    assert_eq!(task(registry, &elsewhere).await["state"], "queued", "never offered to it again");
    worker.signal("TERM");
    assert!(worker.exited("the robot to stop").await.success());
}
