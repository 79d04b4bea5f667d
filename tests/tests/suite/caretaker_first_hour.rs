//! A caretaker's first hour, on a 390 px wide phone in real Chromium, against the real registry
//! and real simulated robots: log in; register the tag a robot just read as "Bedside lamp" in
//! the bedroom, touching no other field; find no internal identifier on its page; ask a robot
//! to turn it off and see, on the Tasks page, the robot decline and why; see what a robot saw
//! on a seeded lamp's page after it worked there; and find the paper's Table I experiment kept
//! out of the drawer's success rate.

use std::process::Command;
use std::time::{Duration, Instant};

use pps_test_kit::fixtures::{self, DRAWER};
use pps_test_kit::{Registry, WorkingRobot, wait, workspace_bin};
use pps_tests::Browser;
use pps_tests::caretaker_view::assert_plain;
use reqwest::{Method, StatusCode};
use serde_json::json;

const PASSWORD: &str = "correct horse battery";
/// A current phone's viewport.
const PHONE: (u32, u32) = (390, 844);
/// The seeded lamp, a device of the simulated room.
const SEEDED_LAMP: &str = "355AB1C60000003000000001";
/// The tag the caretaker sticks on her bedside lamp, a lamp no simulated room has.
const BEDSIDE_LAMP: &str = "E20034120000000000009003";

#[tokio::test]
async fn a_caretakers_first_hour() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let stretch = fixtures::robot(&registry, "stretch-1", "stretch").await;

    // The robot reads the new tag; nobody registered it, so the registry notes it.
    let read = format!("/api/v1/robots/stretch-1/tags/{BEDSIDE_LAMP}");
    let (status, _) = registry.call(Method::GET, &read, &stretch, None, &[]).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    wait::until("the inbox to list the tag the robot read", || async {
        registry.get("/api/v1/inbox").await.to_string().contains(BEDSIDE_LAMP).then_some(())
    })
    .await;
    let _robot = WorkingRobot::start(&registry, "stretch-1", &stretch);

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    assert_eq!(page.eval("return window.innerWidth").await, 390);
    page.log_in("anna", PASSWORD).await;

    // Register it by kind, name and room alone.
    page.click("a[data-nav=register]").await;
    page.click(&format!(".inbox button[data-epc='{BEDSIDE_LAMP}']")).await;
    page.click("button.template[data-template='lamp']").await;
    page.fill("[data-focus-key='/properties/name']", "Bedside lamp").await;
    page.fill("[data-focus-key='/properties/location/room']", "bedroom").await;
    page.click_text("button", "Register tag").await;
    page.wait_for_text("h1.tag-title", "Bedside lamp").await;
    page.wait_for_text("main .status", "Saved “Bedside lamp”").await;
    let bedside = registry.get(&format!("/api/v1/tags/{BEDSIDE_LAMP}")).await;
    assert_eq!(bedside["properties"]["location"]["room"], "bedroom");
    assert_plain(&page, &bedside).await;

    // Ask a robot to turn it off: the only robot at work has no such lamp in its room, says so
    // at once, and the Tasks page shows it.
    page.click("button.ask[data-action=off]").await;
    page.click_text(".ask-control form button[type=submit]", "Ask").await;
    page.wait_for_text(".ask-control .status", "Asked").await;
    let asked_at = Instant::now();
    page.click("a[data-nav=tasks]").await;
    let stuck = page.wait_for_text("table.tasks .stuck", "no device in its simulated room").await;
    assert!(asked_at.elapsed() < Duration::from_secs(10), "seen after {:?}", asked_at.elapsed());
    assert!(stuck.text().await.unwrap().contains(
        "stretch-1 declined: no device in its simulated room has this tag; no other robot can do it"
    ));
    let decline = page.wait_for("table.tasks .declines li").await.text().await.unwrap();
    assert!(decline.starts_with("stretch-1 declined ("), "{decline}");

    // A robot does something on a seeded lamp: its page shows what the robot saw.
    let body = json!({ "epc": SEEDED_LAMP, "action": "on" });
    let (status, task) =
        registry.call(Method::POST, "/api/v1/tasks", &registry.admin_token, Some(&body), &[]).await;
    assert_eq!(status, StatusCode::CREATED, "{task}");
    let task_path = format!("/api/v1/tasks/{}", task["id"].as_str().unwrap());
    wait::until("the robot to finish the lamp's task", || async {
        let task = registry.get(&task_path).await;
        (task["state"] == "done").then_some(())
    })
    .await;
    page.open(&format!("/#/tags/{SEEDED_LAMP}")).await;
    let seen = "section[aria-labelledby=seen-h] img.picture";
    page.wait_until(
        "the robot's picture to load",
        &format!("document.querySelector('{seen}')?.naturalWidth > 0"),
    )
    .await;
    let alt = page.wait_for(seen).await.attr("alt").await.unwrap().unwrap_or_default();
    assert!(alt.starts_with("What stretch-1 saw"), "{alt}");

    // The paper's Table I, run as an experiment, stays out of the drawer's success rate.
    let el_e = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let table_one = Command::new(workspace_bin("pps-trials"))
        .args(["--server", &registry.url, "--robot", "el-e-1", "--json"])
        .env("PPS_TOKEN", &el_e)
        .output()
        .expect("pps-trials runs");
    assert!(table_one.status.success(), "{}", String::from_utf8_lossy(&table_one.stderr));
    let stats = registry.get(&format!("/api/v1/tags/{DRAWER}/stats")).await;
    let experiments = stats["not_counted"]["experiment"].as_u64().unwrap();
    assert!(experiments >= 8, "Table I tries the drawer 8 times or more: {stats}");
    assert_eq!(stats["groups"], json!([]), "no real use of the drawer yet: {stats}");
    page.open(&format!("/#/tags/{DRAWER}")).await;
    page.wait_for_text(
        ".counted",
        &format!("Real use only; {experiments} experiment trials not counted."),
    )
    .await;
    page.wait_for_text("section[aria-labelledby=rates-h]", "No trials of real use yet").await;
    page.close().await;
}
