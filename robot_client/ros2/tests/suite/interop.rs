//! pps-ros2 against a DDS we did not write: Cyclone DDS's Python binding (the DDS under ROS 2's
//! `rmw_cyclonedds`) plays the robot and the operator, with the real registry, all inside a
//! loopback-only network namespace.

use crate::support::netns::isolated;
use crate::support::{PATIENCE, Peer, RosNode, logged_times, registry, stored_trial};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use pps_robot::navigation::{ApproachParams, plan_approach};
use pps_robot::perception::{tag_color, tag_size};
use pps_robot::sim::{
    CaptureSettings, DeviceKind, Room, SceneCapture, StartDirection, capture_scene,
};
use pps_test_kit::wait::try_wait_until;
use serde_json::{Value, json};

/// Writes the scene as the peer reads it: raw RGB rows, raw float32 x y z, and the camera.
fn write_scene(scene: &SceneCapture, dir: &std::path::Path) {
    std::fs::write(dir.join("image.rgb"), &scene.image.rgb).unwrap();
    let xyz: Vec<u8> = scene
        .cloud
        .points
        .iter()
        .flat_map(|p| [p.x, p.y, p.z])
        .flat_map(f32::to_le_bytes)
        .collect();
    std::fs::write(dir.join("cloud.xyz"), xyz).unwrap();
    let c = &scene.calibration;
    let q = c.base_from_camera.rotation;
    let meta = json!({
        "width": c.intrinsics.width, "height": c.intrinsics.height,
        "fx": c.intrinsics.fx, "fy": c.intrinsics.fy, "cx": c.intrinsics.cx, "cy": c.intrinsics.cy,
        "translation": c.base_from_camera.translation.vector.as_slice(),
        "rotation_xyzw": [q.i, q.j, q.k, q.w],
    });
    std::fs::write(dir.join("scene.json"), meta.to_string()).unwrap();
}

fn vector(value: &Value) -> Vec<f64> {
    value.as_array().expect("an array").iter().map(|v| v.as_f64().expect("a number")).collect()
}

fn matched(peer: &mut Peer, node: &RosNode) {
    let answer = peer.command(json!({"wait_matched": 60}));
    assert_eq!(answer["matched"], true, "{answer}\nnode log:\n{}", node.log());
}

#[tokio::test(flavor = "multi_thread")]
async fn a_click_on_a_rendered_scene_gives_the_tag_pose_and_the_goal() {
    if !isolated("interop::a_click_on_a_rendered_scene_gives_the_tag_pose_and_the_goal") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = capture_scene(
        Room::paper(),
        DeviceKind::LightSwitch,
        StartDirection::PAPER[0],
        1.5,
        3,
        // Full size: a 3.7 MB image and a 2.4 MB cloud arrive as thousands of fragments.
        &CaptureSettings::full(),
    );
    write_scene(&scene, dir.path());
    let expected = plan_approach(
        &scene.image,
        &scene.cloud,
        &scene.calibration,
        &scene.target,
        &ApproachParams::default(),
    )
    .unwrap();
    let tag = expected.tag.as_ref().expect("the library finds the tag").nearest();
    let waypoint = expected.waypoint.as_ref().expect("the library finds a waypoint");

    let (server, token) = registry().await;
    let node = RosNode::start(&server, &token, &dir.path().join("state"));
    let mut peer = Peer::start();
    matched(&mut peer, &node);
    // A click before any cloud is answered with nothing, and said once in words.
    let t = scene.target;
    for _ in 0..2 {
        let early = peer.command(json!({"click": [t.x, t.y, t.z], "timeout": 0.5}));
        assert!(early["tag_pose"].is_null() && early["goal_pose"].is_null(), "{early}");
    }
    let streaming = peer.command(json!({"scene": dir.path()}));
    assert_eq!(streaming["streaming"]["points"], scene.cloud.len(), "{streaming}");
    let answer = peer.command(json!({"click": [t.x, t.y, t.z], "timeout": 60}));
    assert!(answer["tag_pose"].is_object(), "no tag pose: {answer}\nnode log:\n{}", node.log());
    assert!(answer["goal_pose"].is_object(), "no goal: {answer}\nnode log:\n{}", node.log());

    let tag_pose = &answer["tag_pose"];
    assert_eq!(tag_pose["frame"], "base_link");
    let at = Point3::from_slice(&vector(&tag_pose["position"]));
    assert!(
        (at - tag.centroid).norm() < 1e-6,
        "the node's tag {at} is not the library's {}",
        tag.centroid
    );
    assert!(
        (at - scene.tag_truth).norm() < 0.03,
        "tag {at} is not at the truth {}",
        scene.tag_truth
    );
    let q = vector(&tag_pose["orientation_xyzw"]);
    let rotation =
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2]));
    let into_plane = rotation * Vector3::x();
    let normal = expected.backing_plane.as_ref().unwrap().normal;
    assert!((into_plane + normal).norm() < 1e-6, "x {into_plane} is not −normal {normal}");
    assert!(into_plane.dot(&scene.tag_normal) < -0.95, "x does not point into the wall");

    let goal = &answer["goal_pose"];
    let goal_at = vector(&goal["position"]);
    assert!(
        (goal_at[0] - waypoint.position.x).abs() < 1e-6
            && (goal_at[1] - waypoint.position.y).abs() < 1e-6
    );
    assert_eq!(goal_at[2], 0.0, "the goal is on the floor");
    let gq = vector(&goal["orientation_xyzw"]);
    let yaw =
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(gq[3], gq[0], gq[1], gq[2]))
            .euler_angles()
            .2;
    assert!((yaw - waypoint.yaw).abs() < 1e-6, "yaw {yaw} is not {}", waypoint.yaw);
    let standoff = (Point3::new(goal_at[0], goal_at[1], 0.0) - Point3::new(at.x, at.y, 0.0)).norm();
    assert!((standoff - 0.5).abs() < 0.05, "the goal is {standoff:.3} m from the tag");
    assert!(answer["markers"].as_u64().unwrap_or(0) >= 6, "markers: {answer}");
    let said = node
        .log()
        .matches("a point was clicked before any point cloud or depth image arrived")
        .count();
    assert_eq!(said, 1, "the early clicks were to be said once:\n{}", node.log());

    // The trial that follows the click carries what the click saw, as `pps-robot run`'s do.
    let id = "5c0ffee0-1d2e-4f3a-8b4c-5d6e7f809a1b";
    let switch = DeviceKind::LightSwitch.epc().as_hex().to_owned();
    assert_eq!(peer.command(json!({"trial": trial_now(id, &switch)}))["sent"], true);
    logged(&node, &format!("trial {id} recorded with its picture")).await;
    let (status, kind, png) = server.get_bytes(&format!("/api/v1/trials/{id}/picture")).await;
    assert_eq!((status.as_u16(), kind.as_str()), (200, "image/png"), "node log:\n{}", node.log());
    let picture = image_size(&png);
    assert!(picture.0 >= 64 && picture.0 <= 320, "a view around the tag: {picture:?}");
    assert!(png.len() <= 200 * 1024);
    // The view went with that trial; the next one has none.
    let next = "5c0ffee0-1d2e-4f3a-8b4c-5d6e7f809a1c";
    assert_eq!(peer.command(json!({"trial": trial_now(next, &switch)}))["sent"], true);
    logged(&node, &format!("trial {next} recorded")).await;
    let (status, _, _) = server.get_bytes(&format!("/api/v1/trials/{next}/picture")).await;
    assert_eq!(status, 404, "a click's view goes with one trial");
}

#[tokio::test(flavor = "multi_thread")]
async fn with_no_picture_the_trial_after_a_click_goes_without_one() {
    if !isolated("interop::with_no_picture_the_trial_after_a_click_goes_without_one") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = capture_scene(
        Room::paper(),
        DeviceKind::LightSwitch,
        StartDirection::PAPER[0],
        1.5,
        3,
        &CaptureSettings::small(),
    );
    write_scene(&scene, dir.path());
    let (server, token) = registry().await;
    let node = RosNode::start_with(&server, &token, &dir.path().join("state"), &["--no-picture"]);
    let mut peer = Peer::start();
    matched(&mut peer, &node);
    peer.command(json!({"scene": dir.path()}));
    let t = scene.target;
    let answer = peer.command(json!({"click": [t.x, t.y, t.z], "timeout": 60}));
    assert!(answer["tag_pose"].is_object(), "{answer}\nnode log:\n{}", node.log());
    let id = "5c0ffee0-1d2e-4f3a-8b4c-5d6e7f809a2b";
    let switch = DeviceKind::LightSwitch.epc().as_hex().to_owned();
    assert_eq!(peer.command(json!({"trial": trial_now(id, &switch)}))["sent"], true);
    logged(&node, &format!("trial {id} recorded")).await;
    stored_trial(&server, id, &node).await;
    let (status, _, _) = server.get_bytes(&format!("/api/v1/trials/{id}/picture")).await;
    assert_eq!(status, 404, "--no-picture sends none");
}

/// A click at `t` that the node answers with a tag's pose.
fn click_to_a_tag(peer: &mut Peer, node: &RosNode, t: &Point3<f64>) {
    let answer = peer.command(json!({"click": [t.x, t.y, t.z], "timeout": 60}));
    assert!(answer["tag_pose"].is_object(), "{answer}\nnode log:\n{}", node.log());
}

/// Waits until the node has logged `text`.
async fn logged(node: &RosNode, text: &str) {
    logged_times(node, text, 1).await;
}

/// A PNG's width and height, from its header.
fn image_size(png: &[u8]) -> (u32, u32) {
    assert_eq!(&png[1..4], b"PNG", "not a PNG");
    let word = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

/// A trial the robot did just now, after the click.
fn trial_now(id: &str, epc: &str) -> Value {
    let format = &time::format_description::well_known::Rfc3339;
    let now = time::OffsetDateTime::now_utc();
    let mut trial = trial(id, epc);
    trial["started_at"] = json!(now.format(format).unwrap());
    trial["finished_at"] = json!((now + time::Duration::seconds(20)).format(format).unwrap());
    trial
}

fn trial(id: &str, epc: &str) -> Value {
    json!({
        "id": id, "epc": epc, "robot": "el-e-1", "action": "on", "behavior": "push_top",
        "started_at": "2026-12-01T10:00:00Z", "finished_at": "2026-12-01T10:00:20Z",
        "outcome": "success", "confirmed": true,
        "detector": {"brightness_change": 41.5}, "forces": [], "measurements": {"via": "ros2"}
    })
}

#[tokio::test(flavor = "multi_thread")]
async fn inventory_rounds_give_entries_and_trials_are_stored() {
    if !isolated("interop::inventory_rounds_give_entries_and_trials_are_stored") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (server, token) = registry().await;
    let node = RosNode::start(&server, &token, &dir.path().join("state"));
    let mut peer = Peer::start();
    matched(&mut peer, &node);

    let switch = DeviceKind::LightSwitch.epc().as_hex().to_owned();
    let drawer = DeviceKind::Drawer.epc().as_hex().to_owned();
    let answer = peer.command(json!({"rfid": [
        [drawer, -61.0, 0], [switch, -47.0, 1], [switch, -49.0, 2], [drawer, -60.0, 3]
    ]}));
    let entry = &answer["entry"];
    assert_eq!(entry["error"], "", "{answer}\nnode log:\n{}", node.log());
    assert_eq!(entry["epc"], switch.as_str());
    assert_eq!(entry["ambiguous"], false);
    let document: Value = serde_json::from_str(entry["entry_json"].as_str().unwrap()).unwrap();
    assert_eq!(document["epc"], switch.as_str());
    assert_eq!(document["robot"], "el-e-1");
    assert_eq!(entry["revision"], format!("r{}", document["revision"]));
    let stored = server.get(&format!("/api/v1/robots/el-e-1/tags/{switch}")).await;
    assert_eq!(document["entry"], stored["entry"], "the entry is the registry's");
    // EL-E here lacks pull_lamp, so the lamp's actions are unavailable to it.
    let lamp = DeviceKind::Lamp.epc().as_hex().to_owned();
    let answer = peer.command(json!({"rfid": [[lamp, -45.0, 0]]}));
    let unavailable =
        answer["entry"]["unavailable_actions"].as_array().cloned().unwrap_or_default();
    assert!(unavailable.contains(&json!("on")), "{answer}");

    let answer = peer.command(json!({"rfid": [["E2003412DEADBEEF00000001", -50.0, 1]]}));
    let error = answer["entry"]["error"].as_str().unwrap_or_default();
    assert!(error.contains("not registered"), "{answer}");
    assert_eq!(answer["entry"]["entry_json"], "");

    let id = "7d1f2b9e-4c3a-4e55-9a41-0c2d9b6e8f10";
    assert_eq!(peer.command(json!({"trial": trial(id, &switch)}))["sent"], true);
    let stored = stored_trial(&server, id, &node).await;
    assert_eq!(stored["epc"], switch.as_str());
    assert_eq!(stored["measurements"]["via"], "ros2");
    let (status, _, _) = server.get_bytes(&format!("/api/v1/trials/{id}/picture")).await;
    assert_eq!(status, 404, "no click, so no view to send with the trial");
    // Sent twice (a peer retrying), still stored once.
    assert_eq!(peer.command(json!({"trial": trial(id, &switch)}))["sent"], true);
    logged_times(&node, &format!("trial {id} recorded"), 2).await;
    let listed = server.get("/api/v1/trials?robot=el-e-1").await;
    let items = listed["items"].as_array().cloned().unwrap_or_default();
    assert_eq!(items.iter().filter(|t| t["id"] == id).count(), 1, "{listed}");
}

#[tokio::test(flavor = "multi_thread")]
async fn with_the_registry_away_entries_still_answer_and_trials_wait_in_the_outbox() {
    if !isolated(
        "interop::with_the_registry_away_entries_still_answer_and_trials_wait_in_the_outbox",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mut server, token) = registry().await;
    let node = RosNode::start(&server, &token, &dir.path().join("state"));
    let mut peer = Peer::start();
    matched(&mut peer, &node);
    // The node read the home's tags at start; the registry then goes away.
    logged(&node, "5 tags known from the registry").await;
    server.kill();

    let drawer = DeviceKind::Drawer.epc().as_hex().to_owned();
    let answer = peer.command(json!({"rfid": [[drawer, -45.0, 2]]}));
    assert_eq!(answer["entry"]["error"], "", "offline, from the cache: {answer}\n{}", node.log());
    assert_eq!(answer["entry"]["epc"], drawer.as_str());
    let document: Value =
        serde_json::from_str(answer["entry"]["entry_json"].as_str().unwrap()).unwrap();
    assert_eq!(document["entry"]["properties"]["type"], "drawer");
    let unknown = peer.command(json!({"rfid": [["E2003412DEADBEEF00000002", -50.0, 1]]}));
    let error = unknown["entry"]["error"].as_str().unwrap_or_default();
    assert!(error.contains("unreachable"), "an unknown tag offline says why: {unknown}");

    let id = "0b6f3c1e-2d4a-4f70-8e19-5a7c3d2e1f00";
    assert_eq!(peer.command(json!({"trial": trial(id, &drawer)}))["sent"], true);
    logged(&node, &format!("trial {id} kept in the outbox")).await;
    server.restart().await;
    let stored = stored_trial(&server, id, &node).await;
    assert_eq!(stored["epc"], drawer.as_str());
}

#[tokio::test(flavor = "multi_thread")]
async fn trials_after_a_confirmed_read_carry_the_tag_s_colour_and_teach_the_registry() {
    if !isolated(
        "interop::trials_after_a_confirmed_read_carry_the_tag_s_colour_and_teach_the_registry",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = capture_scene(
        Room::paper(),
        DeviceKind::LightSwitch,
        StartDirection::PAPER[0],
        1.5,
        3,
        &CaptureSettings::small(),
    );
    write_scene(&scene, dir.path());
    // What `pps-robot run` sends for the same look: the same function on the same plan.
    let params = ApproachParams::default();
    let plan =
        plan_approach(&scene.image, &scene.cloud, &scene.calibration, &scene.target, &params)
            .unwrap();
    let tag = plan.tag.as_ref().expect("the library finds the tag").nearest();
    let expected = tag_color(&scene.image, &scene.calibration, tag, &params.tag).unwrap();
    let expected = serde_json::to_value(expected).unwrap();
    let wall = plan.backing_plane.as_ref().expect("the library finds the switch's wall");
    let size = tag_size(&scene.image, &scene.calibration, tag, &params.tag, &wall.normal)
        .expect("the switch's foam is measured");
    let size = serde_json::to_value(size).unwrap();

    let (server, token) = registry().await;
    // Without pictures: the colour does not depend on them.
    let node = RosNode::start_with(&server, &token, &dir.path().join("state"), &["--no-picture"]);
    let mut peer = Peer::start();
    matched(&mut peer, &node);
    peer.command(json!({"scene": dir.path()}));
    let switch = DeviceKind::LightSwitch.epc().as_hex().to_owned();
    let drawer = DeviceKind::Drawer.epc().as_hex().to_owned();
    let t = scene.target;
    let learned =
        |entry: &Value| entry["entry"]["properties"]["learned_color_segmentation"].clone();
    let entry_path = format!("/api/v1/robots/el-e-1/tags/{switch}");

    // The fingers read another tag, or two alike: the pixels are not known to be the switch's.
    let unconfirmed =
        [json!([[drawer, -45.0, 1]]), json!([[switch, -45.0, 1], [drawer, -46.0, 2]])];
    for (n, round) in unconfirmed.into_iter().enumerate() {
        click_to_a_tag(&mut peer, &node, &t);
        peer.command(json!({"rfid": round}));
        let id = format!("c010a000-0000-4000-8000-00000000000{n}");
        assert_eq!(peer.command(json!({"trial": trial_now(&id, &switch)}))["sent"], true);
        let stored = stored_trial(&server, &id, &node).await;
        assert!(stored.get("tag_color").is_none_or(Value::is_null), "{n}: {stored}");
        assert!(stored.get("tag_size").is_none_or(Value::is_null), "{n}: {stored}");
    }

    // Read after each click: the trials carry the colour, and the third teaches the registry.
    for n in 1..=3 {
        click_to_a_tag(&mut peer, &node, &t);
        let answer = peer.command(json!({"rfid": [[switch, -45.0, 1], [drawer, -60.0, 2]]}));
        assert_eq!(answer["entry"]["ambiguous"], false, "{answer}");
        let id = format!("c010a000-0000-4000-8000-00000000001{n}");
        assert_eq!(peer.command(json!({"trial": trial_now(&id, &switch)}))["sent"], true);
        logged(&node, &format!("trial {id} recorded with its tag's colour and its tag's size"))
            .await;
        let stored = stored_trial(&server, &id, &node).await;
        assert_eq!(stored["tag_color"], expected, "trial {n}");
        assert_eq!(stored["tag_size"], size, "trial {n}");
        let entry = server.get(&entry_path).await;
        assert_eq!(learned(&entry).is_object(), n == 3, "after {n} confirmed reads: {entry}");
    }
    let entry = server.get(&entry_path).await;
    assert_eq!(learned(&entry)["trials"], 3, "{entry}");
    assert_eq!(entry["provenance"]["/properties/learned_color_segmentation/hue_deg"], "learned");
    assert_eq!(entry["entry"]["properties"]["tag_size"], size, "three alike: their medians");
    assert_eq!(entry["provenance"]["/properties/tag_size/width"], "learned");
    assert!(entry["entry"]["properties"]["household_color_segmentation"].is_object(), "{entry}");

    // Once the change feed has brought the learned entry, the node's clicks look for it.
    let learned_colour = "(learned from 3 confirmed reads of this household's tags)";
    let looked = try_wait_until(PATIENCE, || {
        click_to_a_tag(&mut peer, &node, &t);
        let said = node.log().contains(learned_colour);
        async move { said.then_some(()) }
    });
    looked.await.unwrap_or_else(|| panic!("never looked for the learned colour:\n{}", node.log()));
}
