//! The caretakers' UI speaks plainly: registering asks for the kind of device, a name and a
//! room; a tag's page shows no internal identifier until the advanced section is opened, and
//! remembers that per user; a save is confirmed in words; errors stay beside what they are
//! about and in view; a success rate's colour says how good it is. On a 390 px wide phone.

use pps_test_kit::fixtures::{self, ADA_SWITCH, DRAWER};
use pps_test_kit::{Registry, wait};
use pps_tests::caretaker_view::{assert_plain, visible_text};
use pps_tests::{Browser, Session};
use reqwest::StatusCode;
use serde_json::{Value, json};

const PASSWORD: &str = "correct horse battery";
/// A current phone's viewport.
const PHONE: (u32, u32) = (390, 844);
const LAMP: &str = "355AB1C60000003000000001";

/// Whether the advanced section is open.
async fn advanced_open(page: &Session) -> bool {
    page.eval("return document.querySelector('details.advanced').open").await == json!(true)
}

/// `value` with every number as a float: the registry writes 3.0 as 3.
fn as_floats(value: Value) -> Value {
    match value {
        Value::Number(n) => json!(n.as_f64().unwrap()),
        Value::Array(items) => Value::Array(items.into_iter().map(as_floats).collect()),
        Value::Object(map) => {
            Value::Object(map.into_iter().map(|(k, v)| (k, as_floats(v))).collect())
        }
        other => other,
    }
}

/// `entry` without what a caretaker types (name, room), the EPC and the read-only fields.
fn beyond_the_caretakers_fields(entry: &Value) -> Value {
    let mut entry = entry.clone();
    let object = entry.as_object_mut().unwrap();
    for key in ["epc", "epc_uri", "revision", "updated_at", "updated_by", "archived"] {
        object.remove(key);
    }
    let properties = entry["properties"].as_object_mut().unwrap();
    properties.remove("name");
    properties["location"].as_object_mut().unwrap().remove("room");
    as_floats(entry)
}

#[tokio::test]
async fn a_caretaker_registers_the_tag_a_robot_read_by_kind_name_and_room_and_sees_it_plainly() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    registry.add_user("bert", "caretaker", PASSWORD);
    let epc = "E20034120000000000009002";
    let robot = registry.token("robot", "stretch-1");
    let read = format!("/api/v1/robots/stretch-1/tags/{epc}");
    let (status, _) = registry.call(reqwest::Method::GET, &read, &robot, None, &[]).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    wait::until("the inbox to list the unknown EPC", || async {
        registry.get("/api/v1/inbox").await.to_string().contains(epc).then_some(())
    })
    .await;

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    assert_eq!(page.eval("return window.innerWidth").await, 390);
    page.log_in("anna", PASSWORD).await;
    page.click("a[data-nav=register]").await;
    page.click(&format!(".inbox button[data-epc='{epc}']")).await;
    page.click("button.template[data-template='lamp']").await;
    page.wait_for("[data-focus-key='/properties/name']").await;

    // The form asks for a name and a room, nothing else; it fits the phone and is short.
    let asked = page
        .eval(
            "return [...document.querySelectorAll('.entry-form input, .entry-form select, \
             .entry-form textarea')].filter((e) => e.checkVisibility() && !e.readOnly)\
             .map((e) => e.dataset.focusKey)",
        )
        .await;
    assert_eq!(asked, json!(["/properties/name", "/properties/location/room"]));
    assert!(page.fits_width().await, "the register form scrolls sideways on a phone");
    let height = page.eval("return document.documentElement.scrollHeight").await;
    assert!(height.as_u64().unwrap() < 1800, "the register page is {height} px tall");

    page.fill("[data-focus-key='/properties/name']", "Bedside lamp").await;
    page.fill("[data-focus-key='/properties/location/room']", "bedroom").await;
    page.wait_for_text(".save-bar .status", "No problems found").await;
    page.click_text("button", "Register tag").await;
    page.wait_for_text("h1.tag-title", "Bedside lamp").await;
    let saved = page.wait_for_text("main .status", "Saved “Bedside lamp”").await;
    assert_eq!(saved.attr("role").await.unwrap().as_deref(), Some("status"), "announced");

    // Every value but the name and the room came from the lamp's template.
    let stored = registry.get(&format!("/api/v1/tags/{epc}")).await;
    assert_eq!(stored["properties"]["name"], "Bedside lamp");
    assert_eq!(stored["properties"]["location"]["room"], "bedroom");
    let templates = registry.get("/assets/templates.json").await;
    let lamp = templates.as_array().unwrap().iter().find(|t| t["properties"]["type"] == "lamp");
    assert_eq!(beyond_the_caretakers_fields(&stored), beyond_the_caretakers_fields(lamp.unwrap()));

    // What a caretaker knows, in words; no internal identifier.
    let shown = visible_text(&page).await;
    for words in ["Lamp with a pull chain", "bedroom", "Turn off", "Turn on", "How well it goes"] {
        assert!(shown.contains(words), "{words:?} is not shown in:\n{shown}");
    }
    assert_plain(&page, &stored).await;
    assert!(page.fits_width().await, "the tag page scrolls sideways on a phone");

    // The advanced section holds them, and stays open for anna once she opened it.
    assert!(!advanced_open(&page).await, "closed by default");
    page.click("details.advanced > summary").await;
    page.wait_for_text("details.advanced", epc).await;
    page.wait_for_text("details.advanced", "pull_chain").await;
    page.client.refresh().await.unwrap();
    page.wait_for_text("h1.tag-title", "Bedside lamp").await;
    assert!(advanced_open(&page).await, "remembered across a reload");
    assert!(!visible_text(&page).await.contains("Saved"), "the confirmation is said once");

    // Per user: bert, in the same browser, starts closed; anna finds it as she left it.
    page.click_text("button", "Log out").await;
    page.log_in("bert", PASSWORD).await;
    page.open(&format!("/#/tags/{epc}")).await;
    page.wait_for_text("h1.tag-title", "Bedside lamp").await;
    assert!(!advanced_open(&page).await, "bert never opened it");
    page.click_text("button", "Log out").await;
    page.log_in("anna", PASSWORD).await;
    page.open(&format!("/#/tags/{epc}")).await;
    page.wait_for_text("h1.tag-title", "Bedside lamp").await;
    assert!(advanced_open(&page).await, "anna opened it");
    page.close().await;
}

#[tokio::test]
async fn an_error_in_the_closed_advanced_section_is_opened_focused_and_in_view() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open(&format!("/#/tags/{ADA_SWITCH}/edit")).await;
    page.wait_for_text(".save-bar .status", "No problems found").await;
    let force = "[data-focus-key='/behaviors/push_top/force_threshold']";
    page.click("details.advanced > summary").await;
    page.fill(force, "500").await;
    page.wait_for_text("details.advanced > summary", "1 field needs attention").await;
    page.click("details.advanced > summary").await;
    page.wait_until("the section to close", "!document.querySelector('details.advanced').open")
        .await;
    page.eval("window.scrollTo(0, 0); return null").await;

    page.click_text("button", "Save changes").await;
    page.wait_for_text(".save-bar .status", "Not saved: 1 problem").await;
    page.wait_until(
        "the force field to be focused and in view",
        &format!(
            "document.activeElement === document.querySelector(\"{force}\") && (() => {{ \
             const r = document.activeElement.getBoundingClientRect(); \
             return r.top >= 0 && r.bottom <= window.innerHeight; }})()"
        ),
    )
    .await;
    let error = "document.activeElement.closest('.field').querySelector('.field-error')";
    page.wait_until("the error beside the field", &format!("!{error}.hidden")).await;
    assert_eq!(registry.get(&format!("/api/v1/tags/{ADA_SWITCH}")).await["revision"], 1);
    page.close().await;
}

#[tokio::test]
async fn a_json_parse_error_shows_above_the_box_and_the_status_line_agrees() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open(&format!("/#/tags/{LAMP}/edit")).await;
    page.wait_for_text(".save-bar .status", "No problems found").await;
    page.click("details.advanced > summary").await;
    page.click_text("button.tab", "JSON").await;
    page.fill("textarea.json", "{ \"epc\": ").await;

    page.wait_for_text(".save-bar .status", "the JSON does not parse").await;
    let placed = page
        .eval(
            "const box = document.querySelector('textarea.json'); \
             const problem = document.getElementById(box.getAttribute('aria-describedby')); \
             return !problem.hidden && problem.textContent.includes('Not valid JSON') \
               && problem.getBoundingClientRect().bottom <= box.getBoundingClientRect().top \
               && box.getAttribute('aria-invalid') === 'true'",
        )
        .await;
    assert_eq!(placed, true, "the parse error sits above the box, tied to it");
    page.click_text("button", "Save changes").await;
    page.wait_for_text(".save-bar .status", "Not saved: the JSON does not parse").await;
    let statuses = page.eval("return document.querySelectorAll('.save-bar .status').length").await;
    assert_eq!(statuses, 1, "one status line");
    assert_eq!(registry.get(&format!("/api/v1/tags/{LAMP}")).await["revision"], 1);
    page.close().await;
}

#[tokio::test]
async fn a_success_rate_is_green_when_good_and_red_when_bad() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let robot = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let (status, _) =
        fixtures::put_trial(&registry, &robot, &fixtures::pull_trial("el-e-1", json!(0.3))).await;
    assert_eq!(status, StatusCode::CREATED);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open(&format!("/#/tags/{DRAWER}")).await;
    let rate = ".rates li[data-action=open] .badge.rate";
    page.wait_for_text(rate, "100 %").await;
    let grade = format!("document.querySelector('{rate}').dataset.grade");
    assert_eq!(page.eval(&format!("return {grade}")).await, "good");
    page.wait_for_text(".rates li[data-action=open]", "Open").await;

    for _ in 0..2 {
        let mut failed = fixtures::pull_trial("el-e-1", json!(0.01));
        failed["outcome"] = "failure".into();
        let (status, _) = fixtures::put_trial(&registry, &robot, &failed).await;
        assert_eq!(status, StatusCode::CREATED);
    }
    page.wait_for_text(rate, "33 %").await;
    assert_eq!(page.eval(&format!("return {grade}")).await, "bad");
    let colour = page
        .eval(&format!("return getComputedStyle(document.querySelector('{rate}')).color"))
        .await;
    assert_eq!(colour, "rgb(155, 28, 28)", "red text for a bad rate");
    page.close().await;
}
