//! After the read the robot acts on what it knows of that tag (issue 34). The household's tags
//! are not all one red: the drawer's towel is orange-red, so the colour learned from all of
//! them (hue 343..27° after three reads of each) reaches from the rocker's red into orange, and
//! with it into plywood. The rocker switch sits in the upper gang of a plywood double plate
//! (7 × 23.5 cm, within the size of a tag when none is registered): looking for the household's
//! colour, the robot takes patch and plate for one tag whose middle lies 5–6 cm below the
//! patch's (the hand at 1.17 m, the patch at 1.22 m), and its press meant for the paddle's
//! upper half lands on the lower half: the light stays off. The plate's orange is a red that
//! colour admits, so the search now divides plate and patch by their two colours, but from the
//! waypoint only roughly: the hand goes to 1.24 m, 2 cm above the patch's middle. Once the EPC
//! is read, the rocker's
//! own colour, learned from its own three reads (hue 353..357°), leaves the wood out: the look
//! again finds the patch 3.8 cm from where the tag was first seen (carried back to the hand by
//! the motions that undo the back-off; through odometry, drifted on the way there and back, it
//! read 5.9 cm), the hand is brought to
//! within 1 cm of the patch's middle, and the light comes on. The trial then carries the
//! patch's colour as that look saw it (median hue 355°), not the colour of the middle of what
//! was first taken for the tag (the plate's wood, median hue 24°).

use pps_robot::experiment::{SimulatedTrial, flush_until_stored, run_simulated, start_up};
use pps_robot::registry::RegistryClient;
use pps_robot::sim::{DeviceKind, Room, RoomOptions, SimBody};
use pps_robot::task::{TaskConfig, TaskReport};
use pps_schema::Outcome;
use serde_json::json;

/// Confirmed reads of each tag the learning takes: the registry's fewest looks for a model.
const READS_EACH: u64 = 3;

/// The paper's room with its drawer towel orange-red.
fn orange_towel_room() -> RoomOptions {
    RoomOptions { orange_towel: true, ..RoomOptions::default() }
}

/// Confirmed reads of the rocker and the drawer in turn, in real use, until each has taught
/// the registry its own colour; the household's reaches over both.
async fn learn_the_households_colours(client: &RegistryClient, body: SimBody) {
    for n in 1..=READS_EACH {
        for (device, action) in [(DeviceKind::AdaLightSwitch, "on"), (DeviceKind::Drawer, "open")] {
            let trial = SimulatedTrial {
                body,
                seed: n,
                room: orange_towel_room(),
                ..SimulatedTrial::new(device, action, None)
            };
            let result = run_simulated(&trial, client, &TaskConfig::default()).await.unwrap();
            assert_eq!(result.report.epc, Some(device.epc()), "{}", result.report);
            flush_until_stored(client).await.unwrap();
        }
    }
}

/// The height a phase (1 to 4) last brought the hand to, from its note "faced the tag, hand at
/// … m".
fn hand_height(report: &TaskReport, phase: usize) -> f64 {
    let note = report.phases[phase - 1]
        .lines
        .iter()
        .rev()
        .find_map(|n| n.strip_prefix("faced the tag, hand at "))
        .unwrap_or_else(|| panic!("phase {phase} brought the hand to the tag: {report}"));
    note.split(" m").next().unwrap().parse().unwrap()
}

#[tokio::test(flavor = "multi_thread")]
async fn the_rockers_own_colour_after_its_read_leaves_the_wooden_plate_out() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    let client = registry.client(dir.path());
    let body = start_up(&client).await.unwrap();
    learn_the_households_colours(&client, body).await;
    let rocker = client.effective_entry(&DeviceKind::AdaLightSwitch.epc()).await.unwrap().entry;
    let properties = &rocker.entry.properties;
    let own = properties.learned_color().expect("the rocker's own colour learned").segmentation;
    let household = properties.household_color().expect("the household's learned").segmentation;
    let arc = |[from, to]: [f64; 2]| (to - from).rem_euclid(360.0);
    assert!(arc(household.hue_deg) > arc(own.hue_deg) + 10.0, "{household:?} vs {own:?}");

    let room = RoomOptions { wooden_rocker_plate: true, ..orange_towel_room() };
    let truth = Room::new(room).device(DeviceKind::AdaLightSwitch).tag_center;
    let trial = SimulatedTrial {
        body,
        room,
        ..SimulatedTrial::new(DeviceKind::AdaLightSwitch, "on", None)
    };
    let result = run_simulated(&trial, &client, &TaskConfig::default()).await.unwrap();
    let report = &result.report;
    let said = report.to_string();
    assert!(said.contains("learned from 6 confirmed reads of this household's tags"), "{said}");
    // Before the read the hand is brought centimetres from the patch's middle.
    let before = hand_height(report, 3);
    assert!(
        (truth.z - before).abs() > 0.015,
        "phase 3's hand at {before:.3} m, the patch at {:.3} m",
        truth.z
    );
    assert!(said.contains("looked again with this tag's own colour"), "{said}");
    let moved = moved_after_the_read(report);
    assert!(moved > 0.03, "the tag {:.1} cm from where it was first seen: {said}", moved * 100.0);
    let after = hand_height(report, 4);
    assert!(
        (after - truth.z).abs() < 0.01,
        "the hand at {after:.3} m, the patch at {:.3} m",
        truth.z
    );
    assert_eq!(report.outcome, Some(Outcome::Success), "{said}");
    assert!(result.achieved, "the light came on: {said}");

    // The trial teaches the patch's red, not the plate's wood that phase 2 took for its middle.
    flush_until_stored(&client).await.unwrap();
    let trials = registry.trials().await;
    let taught = &trials.last().unwrap()["tag_color"]["hue_deg"][1];
    let hue = taught.as_f64().unwrap();
    let [from, to] = own.hue_deg;
    assert!((from..=to).contains(&hue), "the trial's median hue {hue:.1}° against {own:?}");
}

/// The home's tags with their registered sizes: a flip switch's foam, the rocker's 6 × 6 cm
/// patch, the lamp chain's foam, the drawer's towel (the largest) and the trash can's patch.
const SIZES: [(DeviceKind, f64, f64); 5] = [
    (DeviceKind::LightSwitch, 0.03, 0.04),
    (DeviceKind::AdaLightSwitch, 0.06, 0.06),
    (DeviceKind::Lamp, 0.024, 0.06),
    (DeviceKind::Drawer, 0.16, 0.24),
    (DeviceKind::TrashCan, 0.1, 0.08),
];

/// How far phase 4's look after the read put the tag from where it was first seen, metres.
fn moved_after_the_read(report: &TaskReport) -> f64 {
    let note = report.phases[3]
        .lines
        .iter()
        .find_map(|n| Some(n.split_once(": the tag is ")?.1))
        .unwrap_or_else(|| panic!("phase 4 looked again: {report}"));
    note.split(" cm").next().unwrap().parse::<f64>().unwrap() / 100.0
}

/// A red key box as red as the tag hangs on the wall right of the rocker, touching its plate
/// and standing 4 cm out. Bounded by the household's largest tag (the drawer's towel, 17 cm
/// from its middle), the search takes patch and box for one tag 4.4 cm right of the patch's
/// middle, and the fingers press the box: the light stays off. Once the EPC is read, the
/// rocker's own 6 × 6 cm bounds the search at 7 cm: the region, 18 cm across, is divided by
/// colour, the hand is brought to the patch, and the light comes on. (The robot looks from
/// where it first saw the tag, which its way in leads back to; looking from straight back, 3.7
/// cm to the side of that, the region was 19 cm across and also had to be cut to the surface
/// the patch lies on.)
#[tokio::test(flavor = "multi_thread")]
async fn the_rockers_own_size_after_its_read_parts_it_from_a_red_box_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    let client = registry.client(dir.path());
    for (device, width, height) in SIZES {
        registry
            .edit_tag(device.epc().as_hex(), |entry| {
                entry["properties"]["tag_size"] = json!({"width": width, "height": height});
            })
            .await;
    }
    client.sync_entries().await.unwrap();
    let room = RoomOptions { red_box_by_rocker: true, ..RoomOptions::default() };
    let trial =
        SimulatedTrial { room, ..SimulatedTrial::new(DeviceKind::AdaLightSwitch, "on", None) };
    let result = run_simulated(&trial, &client, &TaskConfig::default()).await.unwrap();
    let report = &result.report;
    let said = report.to_string();
    assert!(said.contains("reaching more than 17 cm from its middle is taken for a tag"), "{said}");
    assert!(said.contains("reaching more than 7 cm from its middle is taken for it"), "{said}");
    let after_the_read = report.phases[3].lines.join("\n");
    assert!(
        after_the_read.contains("have the colour of its part nearest the target"),
        "{after_the_read}"
    );
    assert!(said.contains("looked again with the registered colour and its own size (6 × 6 cm)"));
    let moved = moved_after_the_read(report);
    assert!(moved > 0.03, "the tag {:.1} cm from where it was first seen: {said}", moved * 100.0);
    assert_eq!(report.outcome, Some(Outcome::Success), "{said}");
    assert!(result.achieved, "the light came on: {said}");
}
