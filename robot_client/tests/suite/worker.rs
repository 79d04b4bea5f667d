//! A simulated robot that tries a task and stops before acting says so to the registry at once
//! (issue 35: tasks tell the truth, early): the task shows what stopped it and goes to the
//! other robots, rather than standing "being done" until the robot's lease runs out three
//! times and then failing with "the lease ran out".

use std::sync::atomic::AtomicBool;

use pps_robot::sim::{DeviceKind, RoomOptions, SimBody};
use pps_robot::worker::{Said, Worker};
use pps_test_kit::RobotRegistry;
use pps_test_kit::tasks::asked;
use serde_json::json;

#[tokio::test(flavor = "multi_thread")]
async fn a_task_tried_and_stopped_before_acting_is_given_back_with_what_stopped_it() {
    let dir = tempfile::tempdir().unwrap();
    let registry = RobotRegistry::start().await;
    let epc = DeviceKind::AdaLightSwitch.epc().as_hex().to_string();
    let task = asked(&registry, json!({ "epc": epc, "action": "on" })).await;
    // The room's tags painted blue: nothing where the robot is sent is red.
    let room = RoomOptions { red_tags: false, ..RoomOptions::default() };
    let worker = Worker {
        registry: registry.client(dir.path()),
        body: SimBody::ElE,
        room,
        seed: 0,
        max_tasks: Some(1),
        idle_exit: None,
        picture: false,
    };
    let mut said = Vec::new();
    let done = worker.work(&AtomicBool::new(false), |s| said.push(s)).await.unwrap();
    assert_eq!(done, 1);
    let [Said::Task(line)] = said.as_slice() else { panic!("one task said: {said:?}") };
    assert!(
        line.contains("declined after trying: it tried and could not find the tag: "),
        "{line}"
    );

    let id = task["id"].as_str().unwrap();
    let task = registry.get_json(&format!("/api/v1/tasks/{id}")).await;
    assert_eq!(task["state"], "queued", "another robot may still take it: {task}");
    assert_eq!(task["claimed_by"], json!(null), "{task}");
    let declined = &task["declined"][0];
    assert_eq!(declined["robot"], "el-e-1");
    let reason = declined["reason"].as_str().unwrap();
    assert_eq!(
        reason,
        "it tried and could not find the tag: it saw nothing red where you pointed; point at \
         the red tag itself",
        "what the caretaker can do"
    );
    assert_eq!(
        declined["detail"], "no red tag near the pointed location",
        "what stopped it in the robot's own words, apart"
    );
    assert_eq!(
        task["stuck"].as_str().unwrap(),
        format!("el-e-1 declined: {reason}; no other robot can do it"),
    );
}
