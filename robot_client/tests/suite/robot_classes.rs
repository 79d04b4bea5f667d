//! Two robot classes share one registry: the EL-E-like robot and a Stretch-like one whose camera
//! sees the tags' red as orange and whose gripper opens less wide. Both run the same code; what
//! they do differently comes from the entries' `robots` overrides. Without its class's colour
//! override the Stretch-like robot no longer finds a tag, and the EL-E-like one does not notice.

use pps_robot::experiment::{SimulatedTrial, run_simulated, start_up};
use pps_robot::registry::RegistryClient;
use pps_robot::sim::{DeviceKind, SimBody};
use pps_robot::task::TaskConfig;
use pps_schema::Outcome;

const CAPABILITIES: [&str; 5] = ["light_switch", "pull_back", "push", "pull_lamp", "drop"];

async fn lamp_on(client: &RegistryClient) -> pps_robot::experiment::SimulatedResult {
    let trial = SimulatedTrial {
        body: start_up(client).await.unwrap(),
        ..SimulatedTrial::new(DeviceKind::Lamp, "on", None)
    };
    run_simulated(&trial, client, &TaskConfig::default()).await.unwrap()
}

#[tokio::test(flavor = "multi_thread")]
async fn each_class_acts_by_its_overrides_in_the_shared_entries() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    let el_e = registry.client(dir.path());
    let stretch = registry.add_robot("stretch-1", "stretch", &CAPABILITIES, dir.path()).await;
    assert_eq!(start_up(&el_e).await.unwrap(), SimBody::ElE);
    assert_eq!(start_up(&stretch).await.unwrap(), SimBody::Stretch);

    for (client, colour) in [(&el_e, "hue 340..20°"), (&stretch, "hue 16..32°")] {
        let result = lamp_on(client).await;
        let report = &result.report;
        assert_eq!(report.outcome, Some(Outcome::Success), "{report}");
        assert!(result.after.lamp_on);
        assert!(report.to_string().contains(colour), "{report}");
    }
    let stretch_entry = stretch.effective_entry(&DeviceKind::Lamp.epc()).await.unwrap().entry;
    assert_eq!(
        stretch_entry.provenance["/behaviors/pull_chain/gripper_deg"].to_string(),
        "class:stretch"
    );

    // A caretaker deletes the Stretch class's colours from every entry.
    for device in DeviceKind::ALL {
        registry
            .edit_tag(device.epc().as_hex(), |entry| {
                if let Some(robots) = entry["properties"]["robots"].as_object_mut() {
                    robots.remove("stretch");
                }
            })
            .await;
    }
    let result = lamp_on(&stretch).await;
    let report = &result.report;
    assert_eq!(report.outcome, None, "{report}");
    assert!(!report.phases[1].ok, "phase 2 finds no tag: {report}");
    assert!(report.to_string().contains("no red tag near the pointed location"), "{report}");
    let result = lamp_on(&el_e).await;
    assert_eq!(result.report.outcome, Some(Outcome::Success), "{}", result.report);
    assert_eq!(registry.trials().await.len(), 3, "the stretch's last attempt never acted");
}

#[tokio::test(flavor = "multi_thread")]
async fn a_robot_starting_while_the_registry_is_away_keeps_its_class_and_tags() {
    let dir = tempfile::tempdir().unwrap();
    let mut registry = pps_test_kit::RobotRegistry::start().await;
    let stretch = registry.add_robot("stretch-1", "stretch", &CAPABILITIES, dir.path()).await;
    assert_eq!(start_up(&stretch).await.unwrap(), SimBody::Stretch);
    registry.stop().await;

    let result = lamp_on(&stretch).await;
    let report = &result.report;
    assert_eq!(report.outcome, Some(Outcome::Success), "{report}");
    assert!(report.to_string().contains("hue 16..32°"), "{report}");
    assert_eq!(report.waiting_upload, 1, "{report}");

    let never_online = RegistryClient::new(
        &registry.url,
        "token",
        pps_schema::RobotId::parse("stretch-2").unwrap(),
        &dir.path().join("stretch-2"),
    )
    .unwrap();
    let error = start_up(&never_online).await.unwrap_err().to_string();
    assert!(error.contains("knows neither its class nor any tag"), "{error}");
}
