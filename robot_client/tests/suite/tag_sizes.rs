//! Tags' registered sizes reach the robot (issue 34): once every tag of the home has a size, a
//! red thing larger than the home's largest tag is not taken for a tag, and the report says why
//! in the words the search used.

use pps_robot::experiment::{SimulatedTrial, run_simulated};
use pps_robot::sim::DeviceKind;
use pps_robot::task::TaskConfig;
use pps_schema::Outcome;
use serde_json::json;

#[tokio::test(flavor = "multi_thread")]
async fn a_towel_larger_than_every_registered_tag_is_refused_in_words_and_found_at_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    let client = registry.client(dir.path());
    let open = SimulatedTrial::new(DeviceKind::Drawer, "open", None);

    // Every tag registered as a 4 × 4 cm patch: the drawer's 16 × 24 cm towel is larger.
    for device in DeviceKind::ALL {
        registry
            .edit_tag(device.epc().as_hex(), |entry| {
                entry["properties"]["tag_size"] = json!({"width": 0.04, "height": 0.04});
            })
            .await;
    }
    client.sync_entries().await.unwrap();
    let result = run_simulated(&open, &client, &TaskConfig::default()).await.unwrap();
    let report = &result.report;
    assert_eq!(report.outcome, None, "{report}");
    assert!(!report.phases[1].ok, "phase 2 takes no tag: {report}");
    let said = report.to_string();
    assert!(said.contains("no red region reaching more than 6 cm from its middle"), "{report}");
    assert!(said.contains("no tag taken near the pointed location: the red region"), "{report}");
    assert!(said.contains("larger than any tag"), "{report}");
    assert!(
        said.contains("what to do: something red larger than any tag of this home"),
        "{report}"
    );
    // Every size is registered already: the caretaker is asked to move the red thing or point
    // at the tag's middle, not to give a size.
    assert!(said.contains("or point at the middle of the tag"), "{report}");
    assert!(!said.contains("give the tag's size"), "{report}");
    assert!(result.after.drawer_open < 0.01, "the robot did not act");

    // The towel's own size registered: the largest tag of the home, found and pulled.
    registry
        .edit_tag(DeviceKind::Drawer.epc().as_hex(), |entry| {
            entry["properties"]["tag_size"] = json!({"width": 0.16, "height": 0.24});
        })
        .await;
    client.sync_entries().await.unwrap();
    let result = run_simulated(&open, &client, &TaskConfig::default()).await.unwrap();
    let report = &result.report;
    assert_eq!(report.outcome, Some(Outcome::Success), "{report}");
    assert!(report.to_string().contains("reaching more than 17 cm"), "{report}");
    assert!(result.after.drawer_open > 0.15);
}
