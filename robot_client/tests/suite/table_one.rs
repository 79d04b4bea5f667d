//! The paper's Table I protocol (§V): 48 trials in the simulator against an in-process
//! registry, every one of them stored there. All 48 must come out right (the paper got 43), for
//! the EL-E-like robot and for the Stretch-like one, which acts by its class's overrides. In a
//! home (red things beside the tags, the switches 30 cm apart, lacquer, evening light) at most
//! one of the 48 may miss.

use pps_robot::experiment::{flush_until_stored, render_table, run_trials};
use pps_robot::registry::RegistryClient;
use pps_robot::sim::{DeviceKind, RoomOptions};

async fn protocol(
    registry: &pps_test_kit::RobotRegistry,
    client: &RegistryClient,
    room: RoomOptions,
    least: u32,
) {
    let rows = run_trials(client, room, 0, None, false).await.unwrap();
    flush_until_stored(client).await.unwrap();
    println!("{}", render_table(&rows, false));

    let trials: u32 = rows.iter().map(|r| r.trials).sum();
    assert_eq!(trials, 48);
    let robot = client.robot().to_string();
    let stored = registry.trials().await;
    let own = stored.iter().filter(|t| t["robot"] == robot.as_str()).count();
    assert_eq!(own, 48, "every trial is stored in the registry");
    let successes: u32 = rows.iter().map(|r| r.successes).sum();
    assert!(successes >= least, "{successes} of 48 right:\n{}", render_table(&rows, false));
    experiment_kept_apart(registry, &stored).await;
}

/// The protocol's trials are an experiment: the stuck drawer's failures do not count against
/// the drawer in real use, and count only when asked for.
async fn experiment_kept_apart(
    registry: &pps_test_kit::RobotRegistry,
    stored: &[serde_json::Value],
) {
    assert!(stored.iter().all(|t| t["purpose"] == "experiment"), "every trial is an experiment");
    let drawer = DeviceKind::Drawer.epc();
    let on_drawer = stored.iter().filter(|t| t["epc"] == drawer.as_hex()).count();
    assert!(on_drawer > 0);
    let real_use = registry.stats(drawer.as_hex(), None).await;
    assert_eq!(real_use["groups"], serde_json::json!([]), "no real use yet: {real_use}");
    assert_eq!(real_use["not_counted"], serde_json::json!({ "experiment": on_drawer }));
    let with_experiment = registry.stats(drawer.as_hex(), Some("experiment")).await;
    let attempts: usize = with_experiment["groups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["attempts"].as_u64().unwrap() as usize)
        .sum();
    assert_eq!(attempts, on_drawer);
}

async fn second_class(
    registry: &pps_test_kit::RobotRegistry,
    dir: &std::path::Path,
) -> RegistryClient {
    let capabilities = ["light_switch", "pull_back", "push", "pull_lamp", "drop"];
    registry.add_robot("stretch-1", "stretch", &capabilities, dir).await
}

#[tokio::test(flavor = "multi_thread")]
async fn table_one_protocol() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    protocol(&registry, &registry.client(dir.path()), RoomOptions::default(), 48).await;
}

#[tokio::test(flavor = "multi_thread")]
async fn table_one_protocol_for_the_second_robot_class() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    let stretch = second_class(&registry, dir.path()).await;
    protocol(&registry, &stretch, RoomOptions::default(), 48).await;
}

#[tokio::test(flavor = "multi_thread")]
async fn table_one_protocol_in_a_home() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    protocol(&registry, &registry.client(dir.path()), RoomOptions::home(), 47).await;
}

#[tokio::test(flavor = "multi_thread")]
async fn table_one_protocol_in_a_home_for_the_second_robot_class() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    let stretch = second_class(&registry, dir.path()).await;
    protocol(&registry, &stretch, RoomOptions::home(), 47).await;
}
