//! Home Assistant itself, end to end: the caretaker's story of the bridge. The registry with
//! `--mqtt`, a real Mosquitto, a real Home Assistant whose MQTT integration is set up through
//! its own API: the seeded devices appear in their areas, pressing "Turn off" through Home
//! Assistant's REST API becomes a task, a simulated robot does it, and Home Assistant then
//! shows the light off, as the robot's detector saw it.

use std::time::Instant;

use pps_test_kit::fixtures::{self, ADA_SWITCH};
use pps_test_kit::{Registry, WorkingRobot, wait};
use pps_tests::{HomeAssistant, Mosquitto};
use reqwest::Method;
use serde_json::{Value, json};

/// Each device Home Assistant has buttons of, with its area: `name=area;…`, sorted.
const DEVICES_AND_AREAS: &str = "{% set ns = namespace(seen=[]) %}{% for s in states.button %}\
    {% set ns.seen = ns.seen + [device_attr(s.entity_id, 'name') ~ '=' ~ area_name(s.entity_id)] %}\
    {% endfor %}{{ ns.seen | unique | sort | join(';') }}";

async fn state_of(hass: &HomeAssistant, name: &str) -> Option<String> {
    hass.state_named(name).await.and_then(|s| s["state"].as_str().map(str::to_owned))
}

#[tokio::test]
async fn home_assistant_shows_the_tagged_devices_and_a_press_is_done_by_a_robot() {
    let starting = Instant::now();
    let hass = HomeAssistant::start();
    let broker = Mosquitto::start().await;
    let registry = Registry::with_flags(&["--mqtt", &broker.url()]);
    let hass = hass.ready().await;
    eprintln!("Home Assistant answered after {} ms", starting.elapsed().as_millis());
    hass.add_mqtt(broker.port).await;

    let devices = wait::until("Home Assistant to show the five seeded devices", || async {
        let seen = hass.template(DEVICES_AND_AREAS).await;
        (seen.split(';').count() == 5).then_some(seen)
    })
    .await;
    eprintln!("devices in Home Assistant {} ms after it started", starting.elapsed().as_millis());
    // Onboarding made "Living Room" and "Kitchen"; a suggested area joins the area of the same
    // name whatever its case, and "hallway" is new.
    assert_eq!(
        devices,
        "A D A light switch 1=hallway;drawer 1=Kitchen;lamp 1=Living Room;\
         light switch 1=Living Room;trash can 1=Kitchen"
    );
    // No robot online: nothing can be done yet.
    let turn_off = "A D A light switch 1 Turn off";
    assert_eq!(state_of(&hass, turn_off).await.as_deref(), Some("unavailable"));

    let token = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let _robot = WorkingRobot::start(&registry, "el-e-1", &token);
    let button = wait::until("the button to become available", || async {
        let state = hass.state_named(turn_off).await?;
        (state["state"] != "unavailable").then(|| state["entity_id"].as_str().unwrap().to_owned())
    })
    .await;
    // The entity ids docs/home-assistant.md's example automation uses.
    assert_eq!(button, "button.a_d_a_light_switch_1_turn_off");
    let light = "A D A light switch 1";
    let state = hass.state_named(light).await.expect("the light's state entity");
    assert_eq!(state["entity_id"], "binary_sensor.a_d_a_light_switch_1");
    assert_eq!(state["state"], "unknown", "no trial said yet");
    let task_sensor =
        hass.state_named("A D A light switch 1 Robot task").await.expect("a task sensor");
    assert_eq!(task_sensor["entity_id"], "sensor.a_d_a_light_switch_1_robot_task");

    let pressed = Instant::now();
    let entity = json!({ "entity_id": button });
    hass.call(Method::POST, "/api/services/button/press", Some(&entity)).await;
    let task = wait::until("the press to become a task", || async {
        let tasks = registry.get(&format!("/api/v1/tasks?epc={ADA_SWITCH}")).await;
        tasks["items"].as_array()?.first().cloned()
    })
    .await;
    eprintln!("press in Home Assistant to task: {} ms", pressed.elapsed().as_millis());
    assert_eq!(
        (task["action"].as_str(), task["created_by"].as_str()),
        (Some("off"), Some("Home Assistant bridge"))
    );

    let id = task["id"].as_str().unwrap().to_owned();
    let done: Value = wait::until("the robot to do the task", || async {
        let task = registry.get(&format!("/api/v1/tasks/{id}")).await;
        (task["state"] == "done" || task["state"] == "failed").then_some(task)
    })
    .await;
    assert_eq!(done["state"], "done", "{done}");
    let trial = registry.get(&format!("/api/v1/trials/{}", done["trial"].as_str().unwrap())).await;
    assert_eq!(trial["detector"]["saw"], "turned_off", "{trial}");
    let finished = Instant::now();
    wait::until("Home Assistant to show the light off", || async {
        (state_of(&hass, light).await.as_deref() == Some("off")).then_some(())
    })
    .await;
    eprintln!("task done to state in Home Assistant: {} ms", finished.elapsed().as_millis());
    let words = wait::until("the task sensor to say who did it", || async {
        state_of(&hass, "A D A light switch 1 Robot task").await.filter(|s| s.starts_with("done"))
    })
    .await;
    assert_eq!(words, "done by el-e-1");
    eprintln!("whole test: {} ms", starting.elapsed().as_millis());
}
