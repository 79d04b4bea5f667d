//! The Home Assistant bridge against a real Mosquitto, seen by a plain MQTT client as Home
//! Assistant would see it: the seeded tags announced as devices, a press made into one task
//! that a simulated robot does, the state its detector saw, bad messages ignored, an archived
//! tag removed, a retagged one kept, the broker killed and back, a message over 1 MiB, the
//! bridge's goodbye.

use std::time::Instant;

use pps_test_kit::fixtures::{self, ADA_SWITCH, DRAWER};
use pps_test_kit::{Registry, WorkingRobot, wait};
use pps_tests::{Mosquitto, MqttWatch};
use reqwest::Method;
use serde_json::{Value, json};
use time::format_description::well_known::Rfc3339;

const TRASH_CAN: &str = "355AB1C60000005000000001";
const BRIDGE: &str = "pps/bridge/availability";

/// The device id the bridge gives the tag first registered as `epc`.
fn device(epc: &str) -> String {
    format!("pps_{}", epc.to_ascii_lowercase())
}

fn json_on(watch: &MqttWatch, topic: &str) -> Value {
    let payload = watch.last(topic).unwrap_or_else(|| panic!("nothing on {topic}"));
    serde_json::from_slice(&payload).unwrap_or_else(|e| panic!("{topic} is not JSON: {e}"))
}

/// The task sensors announced: one per active tag.
fn task_configs(watch: &MqttWatch) -> Vec<String> {
    watch.topics(|topic| {
        topic.starts_with("homeassistant/sensor/") && topic.ends_with("/task/config")
    })
}

async fn announced(watch: &MqttWatch, tags: usize) {
    wait::until(&format!("{tags} tags announced"), || async {
        (task_configs(watch).len() == tags).then_some(())
    })
    .await;
}

/// The tasks on a tag, newest first.
async fn tasks_on(registry: &Registry, epc: &str) -> Vec<Value> {
    let page = registry.get(&format!("/api/v1/tasks?epc={epc}")).await;
    page["items"].as_array().cloned().unwrap_or_default()
}

#[tokio::test]
async fn a_press_in_home_assistant_is_one_task_a_robot_does_and_the_state_is_what_it_saw() {
    let broker = Mosquitto::start().await;
    let registry = Registry::with_flags(&["--mqtt", &broker.url()]);
    let watch = MqttWatch::connect(broker.port, "watch-press", &["homeassistant/#", "pps/#"]).await;
    let started = Instant::now();
    announced(&watch, 5).await;
    eprintln!("five tags announced {} ms after subscribing", started.elapsed().as_millis());
    watch.until_text(BRIDGE, "online").await;

    let ada = device(ADA_SWITCH);
    let off = json_on(&watch, &format!("homeassistant/button/{ada}/off/config"));
    assert_eq!(off["name"], "Turn off");
    assert_eq!(off["device"]["name"], "A D A light switch 1");
    assert_eq!(off["device"]["suggested_area"], "hallway");
    assert_eq!(off["device"]["identifiers"], json!([ada, ADA_SWITCH]));
    let state = json_on(&watch, &format!("homeassistant/binary_sensor/{ada}/state/config"));
    assert_eq!(state["device_class"], "light");
    let drawer =
        json_on(&watch, &format!("homeassistant/binary_sensor/{}/state/config", device(DRAWER)));
    assert_eq!(drawer["device_class"], "opening");
    assert_eq!(drawer["device"]["suggested_area"], "kitchen");
    assert!(
        watch
            .last(&format!("homeassistant/binary_sensor/{}/state/config", device(TRASH_CAN)))
            .is_none(),
        "a trash can has no two states"
    );
    // No robot is online: nothing can be done, and nothing is known of the light yet.
    watch.until_text(&format!("pps/{ada}/availability"), "offline").await;
    assert_eq!(watch.text(&format!("pps/{ada}/state")), None, "unknown until a trial says");

    let token = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let _robot = WorkingRobot::start(&registry, "el-e-1", &token);
    watch.until_text(&format!("pps/{ada}/availability"), "online").await;

    // What is not a press is ignored; the press after it is taken.
    let press = format!("pps/{ada}/press/off");
    watch.publish(&press, "NOPE").await;
    watch.publish(&format!("pps/{ada}/press/on"), vec![b'P'; 100_000]).await;
    watch.publish(&format!("pps/{}/press/off", device("1234")), "PRESS").await;
    watch.publish(&format!("pps/{ada}/press/explode"), "PRESS").await;
    let pressed = Instant::now();
    watch.publish(&press, "PRESS").await;
    let task = wait::until("the press to become a task", || async {
        tasks_on(&registry, ADA_SWITCH).await.into_iter().next()
    })
    .await;
    eprintln!("press to task: {} ms", pressed.elapsed().as_millis());
    assert_eq!(task["action"], "off");
    assert_eq!(task["created_by"], "Home Assistant bridge");
    for (what, logged) in [
        ("the wrong word", "a press is the payload PRESS, not 4 bytes"),
        ("the oversized payload", "not 100000 bytes"),
        ("the unknown device", "no active tag is that device"),
        ("the unknown action", "the tag has no such action"),
    ] {
        wait::until(&format!("{what} to be logged"), || async {
            registry.logged(logged).then_some(())
        })
        .await;
    }

    let id = task["id"].as_str().unwrap().to_owned();
    let done = wait::until("the robot to finish the task", || async {
        let task = registry.get(&format!("/api/v1/tasks/{id}")).await;
        (task["state"] != "queued" && task["state"] != "claimed").then_some(task)
    })
    .await;
    assert_eq!(done["state"], "done", "{done}");
    watch.until_text(&format!("pps/{ada}/state"), "OFF").await;
    let trial = registry.get(&format!("/api/v1/trials/{}", done["trial"].as_str().unwrap())).await;
    assert_eq!(trial["detector"]["saw"], "turned_off", "{trial}");
    let received = trial["received_at"].as_str().expect("received_at");
    let received = time::OffsetDateTime::parse(received, &Rfc3339).expect("an RFC 3339 time");
    let arrived = time::OffsetDateTime::from(watch.arrived(&format!("pps/{ada}/state")).unwrap());
    eprintln!(
        "trial stored to state on the broker: {} ms",
        (arrived - received).whole_milliseconds()
    );
    watch.until_text(&format!("pps/{ada}/task"), "done by el-e-1").await;
    assert_eq!(tasks_on(&registry, ADA_SWITCH).await.len(), 1, "one press, one task");
}

#[tokio::test]
async fn archived_tags_leave_retagged_ones_stay_and_a_revoked_bridge_asks_nothing() {
    let broker = Mosquitto::start().await;
    let registry = Registry::with_flags(&["--mqtt", &broker.url(), "--mqtt-prefix", "ha/test"]);
    let watch = MqttWatch::connect(broker.port, "watch-archive", &["ha/test/#", "pps/#"]).await;
    wait::until("five tags announced under the prefix", || async {
        (watch.topics(|t| t.starts_with("ha/test/sensor/") && t.ends_with("/task/config")).len()
            == 5)
            .then_some(())
    })
    .await;

    let trash = device(TRASH_CAN);
    let trash_config = format!("ha/test/button/{trash}/drop/config");
    let path = format!("/api/v1/tags/{TRASH_CAN}");
    let seen = registry.request(Method::GET, &path, &registry.admin_token).send().await.unwrap();
    let etag = seen.headers()["etag"].to_str().unwrap().to_owned();
    let (status, body) = registry
        .call(Method::DELETE, &path, &registry.admin_token, None, &[("if-match", &etag)])
        .await;
    assert!(status.is_success(), "{status} {body}");
    wait::until("the archived tag's config to be emptied", || async {
        (watch.last(&trash_config) == Some(Vec::new())).then_some(())
    })
    .await;
    let fresh = MqttWatch::connect(broker.port, "watch-fresh", &["ha/test/#"]).await;
    wait::until("a new subscriber to see four tags", || async {
        (fresh.topics(|t| t.ends_with("/task/config")).len() == 4).then_some(())
    })
    .await;
    assert_eq!(fresh.last(&trash_config), None, "nothing retained for an archived tag");

    // A worn tag replaced: the same device, its new EPC among its identifiers.
    let new_epc = "355AB1C60000004000000099";
    let (status, body) = registry
        .call(
            Method::POST,
            &format!("/api/v1/tags/{DRAWER}/retag"),
            &registry.admin_token,
            Some(&json!({ "new_epc": new_epc })),
            &[],
        )
        .await;
    assert!(status.is_success(), "{status} {body}");
    let drawer = device(DRAWER);
    let open_config = format!("ha/test/button/{drawer}/open/config");
    wait::until("the retagged drawer re-announced", || async {
        let config: Value = serde_json::from_slice(&watch.last(&open_config)?).ok()?;
        (config["device"]["identifiers"] == json!([drawer, new_epc])).then_some(())
    })
    .await;

    // Revoking the bridge's credential refuses presses, said once.
    let tokens = registry.get("/api/v1/tokens").await;
    let items = tokens.as_array().or(tokens["items"].as_array()).expect("a token list").clone();
    let bridge = items.iter().find(|t| t["name"] == "Home Assistant bridge").expect("minted");
    assert_eq!(bridge["role"], "caretaker");
    let path = format!("/api/v1/tokens/{}", bridge["id"].as_str().unwrap());
    let (status, _) = registry.call(Method::DELETE, &path, &registry.admin_token, None, &[]).await;
    assert!(status.is_success());
    watch.publish(&format!("pps/{drawer}/press/open"), "PRESS").await;
    wait::until("the refusal to be logged", || async {
        registry.logged("refused presses from Home Assistant").then_some(())
    })
    .await;
    assert!(tasks_on(&registry, new_epc).await.is_empty(), "a revoked bridge asked for a task");
}

#[tokio::test]
async fn the_bridge_outlives_its_broker_and_says_goodbye() {
    let mut broker = Mosquitto::start().await;
    let registry = Registry::with_flags(&["--mqtt", &broker.url()]);
    let watch =
        MqttWatch::connect(broker.port, "watch-restart", &["homeassistant/#", BRIDGE]).await;
    announced(&watch, 5).await;

    let bridge = registry.get("/api/v1/home-assistant").await;
    assert_eq!(
        bridge,
        json!({
            "bridge": "connected",
            "broker": broker.url(),
            "prefix": "homeassistant",
            "problem": null,
        })
    );

    broker.kill();
    // The registry serves on while the broker is gone, and the admin page says so.
    assert_eq!(registry.get("/api/v1/tags").await["items"].as_array().map(Vec::len), Some(5));
    wait::until("the bridge to say it lost the broker", || async {
        (registry.get("/api/v1/home-assistant").await["bridge"] == "connecting").then_some(())
    })
    .await;
    broker.restart().await;
    let back = Instant::now();
    // The restarted broker lost every retained message: seeing them means they were said again.
    let fresh = MqttWatch::connect(broker.port, "watch-after", &["homeassistant/#", BRIDGE]).await;
    fresh.until_text(BRIDGE, "online").await;
    announced(&fresh, 5).await;
    eprintln!("broker back to everything announced again: {} ms", back.elapsed().as_millis());
    assert_eq!(registry.get("/api/v1/home-assistant").await["bridge"], "connected");

    // Home Assistant restarting asks for everything again.
    let ada_off = format!("homeassistant/button/{}/off/config", device(ADA_SWITCH));
    fresh.publish(&ada_off, "").await;
    fresh.until_text(&ada_off, "").await;
    fresh.publish("homeassistant/status", "online").await;
    wait::until("the re-announcement after Home Assistant came online", || async {
        fresh.last(&ada_off).filter(|payload| !payload.is_empty()).map(drop)
    })
    .await;

    let status = std::process::Command::new("kill")
        .args(["-TERM", &registry.pid().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success());
    fresh.until_text(BRIDGE, "offline").await;
}

#[test]
fn a_broker_url_the_bridge_cannot_use_stops_serve_in_one_sentence() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("pps.db");
    for (url, says) in [
        ("http://broker.lan", "a broker URL starts with mqtt:// or mqtts://, not http://"),
        ("mqtt://broker.lan/topic", "has a path or query"),
    ] {
        let output = std::process::Command::new(pps_test_kit::workspace_bin("pps-server"))
            .args(["serve", "--listen", "127.0.0.1:0", "--mqtt", url, "--db"])
            .arg(&db)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{url} was accepted");
        assert!(stderr.contains(says), "{url}: {stderr}");
        assert!(!db.exists(), "{url}: a refused start left a database behind");
    }
}

#[tokio::test]
async fn a_registry_that_dies_is_marked_offline_by_its_last_will() {
    let broker = Mosquitto::start().await;
    let registry = Registry::with_flags(&["--mqtt", &broker.url()]);
    let watch = MqttWatch::connect(broker.port, "watch-will", &[BRIDGE]).await;
    watch.until_text(BRIDGE, "online").await;
    // Killed outright: no goodbye, so it is the broker that says it.
    drop(registry);
    watch.until_text(BRIDGE, "offline").await;
}

#[tokio::test]
async fn a_message_over_a_mebibyte_ends_only_the_bridges_connection_and_it_comes_back() {
    let broker = Mosquitto::start().await;
    let registry = Registry::with_flags(&["--mqtt", &broker.url()]);
    let watch =
        MqttWatch::connect(broker.port, "watch-oversized", &["homeassistant/#", "pps/#"]).await;
    announced(&watch, 5).await;
    watch.until_text(BRIDGE, "online").await;

    // Emptied here, so that only the bridge announcing again (as it does on every reconnect)
    // fills it.
    let ada = device(ADA_SWITCH);
    let ada_off = format!("homeassistant/button/{ada}/off/config");
    watch.publish(&ada_off, "").await;
    watch.until_text(&ada_off, "").await;

    let press = format!("pps/{ada}/press/off");
    let sent = Instant::now();
    watch.publish(&press, vec![b'P'; 1_100_000]).await;
    wait::until("the oversized message to be logged", || async {
        registry
            .logged(
                "over the bridge's limit of 1048576: that ends the connection, and the bridge \
                 reconnects without it",
            )
            .then_some(())
    })
    .await;
    // The watch would not see this had its own connection ended: its subscriptions would be
    // gone with its session.
    wait::until("the bridge to reconnect and announce again", || async {
        watch.last(&ada_off).filter(|payload| !payload.is_empty()).map(drop)
    })
    .await;
    eprintln!("oversized message to announced again: {} ms", sent.elapsed().as_millis());
    assert_eq!(registry.get("/api/v1/tags").await["items"].as_array().map(Vec::len), Some(5));

    // The oversized message asked for nothing; the next press asks once.
    watch.publish(&press, "PRESS").await;
    wait::until("the press to become a task", || async {
        tasks_on(&registry, ADA_SWITCH).await.into_iter().next()
    })
    .await;
    assert_eq!(tasks_on(&registry, ADA_SWITCH).await.len(), 1, "one press, one task");
}

/// The bridge's lease in the database runs out now, as it would 20 s after its holder died.
/// The lease reads the wall clock and has no clock of its own to move, so its end is moved.
async fn run_the_lease_out(db: &std::path::Path) {
    let options = sqlx::sqlite::SqliteConnectOptions::new().filename(db);
    let mut conn = <sqlx::SqliteConnection as sqlx::Connection>::connect_with(&options)
        .await
        .expect("the registry's database opens");
    let ended = sqlx::query("update bridge_lease set until = '2000-01-01T00:00:00.000Z'")
        .execute(&mut conn)
        .await
        .expect("the lease's end is moved");
    assert_eq!(ended.rows_affected(), 1, "one lease");
}

#[tokio::test]
async fn a_registry_started_after_a_crash_runs_the_bridge_once_the_old_lease_ran_out() {
    let broker = Mosquitto::start().await;
    let mqtt = ["--mqtt", &broker.url()];
    let crashed = Registry::with_flags(&mqtt);
    let watch = MqttWatch::connect(broker.port, "watch-crash", &["homeassistant/#", BRIDGE]).await;
    announced(&watch, 5).await;
    watch.until_text(BRIDGE, "online").await;

    // Killed outright: its lease is not given up.
    let status = std::process::Command::new("kill")
        .args(["-KILL", &crashed.pid().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success());
    watch.until_text(BRIDGE, "offline").await;

    // Started again on the same database: the dead process's lease still stands.
    let restarted = crashed.another_replica(&mqtt);
    wait::until("the restarted registry to stand by", || async {
        restarted
            .logged("another replica runs the Home Assistant bridge; standing by")
            .then_some(())
    })
    .await;
    assert!(!restarted.logged("running the Home Assistant bridge"));

    run_the_lease_out(crashed.db_path()).await;
    let ran_out = Instant::now();
    wait::until("the restarted registry to take the bridge", || async {
        restarted.logged("running the Home Assistant bridge").then_some(())
    })
    .await;
    watch.until_text(BRIDGE, "online").await;
    eprintln!("lease run out to the bridge online again: {} ms", ran_out.elapsed().as_millis());
    assert_eq!(restarted.get("/api/v1/home-assistant").await["bridge"], "connected");
}
