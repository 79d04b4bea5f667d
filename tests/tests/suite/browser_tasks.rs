//! Caretakers ask, robots do, in a real browser: a caretaker asks by keyboard alone for "off"
//! on the rocker switch, a real `pps-robot work` process does it, and the tag's page shows the
//! trial without a reload; the tasks and robots pages say what happened. A task on a tag no
//! robot's room has shows the robot's decline and why it waits on the Tasks page.

use std::time::{Duration, Instant};

use pps_test_kit::fixtures::{self, ADA_SWITCH};
use pps_test_kit::{Registry, WorkingRobot};
use pps_tests::Browser;
use pps_tests::browser::{DESKTOP, PHONE};
use reqwest::{Method, StatusCode};
use serde_json::json;

const PASSWORD: &str = "correct horse battery";
const TAB: &str = "\u{E004}";
const ENTER: &str = "\u{E007}";

#[tokio::test]
async fn a_caretaker_asks_by_keyboard_and_sees_the_robots_trial_arrive() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let token = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let _robot = WorkingRobot::start(&registry, "el-e-1", &token);

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open(&format!("/#/tags/{ADA_SWITCH}")).await;
    page.wait_for_text("#trials", "No robot has tried this tag yet").await;

    // Keyboard alone: Enter on the button, the form takes focus, Tab to the note, type, Tab to
    // the Ask button, Enter.
    let ask = page.wait_for("button.ask[data-action=off]").await;
    assert_eq!(ask.text().await.unwrap(), "Ask a robot to turn it off");
    ask.send_keys(ENTER).await.unwrap();
    page.wait_until("the form to take focus", "document.activeElement?.name === 'who'").await;
    let active = || async { page.client.active_element().await.unwrap() };
    active().await.send_keys(TAB).await.unwrap();
    page.wait_until("the note to take focus", "document.activeElement?.name === 'note'").await;
    active().await.send_keys(&format!("the hallway, please{TAB}")).await.unwrap();
    page.wait_until(
        "the Ask button to take focus",
        "document.activeElement?.textContent === 'Ask'",
    )
    .await;
    active().await.send_keys(ENTER).await.unwrap();
    page.wait_for_text(".ask-control .status", "Asked").await;

    // The robot does it; the page learns of it from the live feed, with no reload.
    page.eval("window.notReloaded = true; return null").await;
    page.wait_for_text("#trials table.trials", "off").await;
    page.wait_for_text(".ask-control .status", "done by el-e-1").await;
    assert_eq!(page.eval("return window.notReloaded === true").await, true, "no reload");
    let tasks = registry.get("/api/v1/tasks").await;
    let task = &tasks["items"][0];
    assert_eq!(task["state"], "done");
    assert_eq!(task["note"], "the hallway, please");
    assert_eq!(task["created_by"], "anna");
    let trial = registry.get(&format!("/api/v1/trials/{}", task["trial"].as_str().unwrap())).await;
    assert_eq!(trial["measurements"]["task"], task["id"]);
    assert!(page.fits_width().await, "the tag page fits a phone");

    page.click("a[data-nav=tasks]").await;
    let row = page.wait_for_text("table.tasks tr", "done by el-e-1").await;
    assert!(row.text().await.unwrap().contains("the hallway, please"));
    page.wait_for(&format!("table.tasks a[data-trial='{}']", task["trial"].as_str().unwrap()))
        .await;
    assert!(page.fits_width().await, "the tasks page fits a phone");
    page.click("a[data-nav=robots]").await;
    page.wait_for_text("#waiting", "Nothing is waiting for a robot").await;
    let row = page.wait_for("table.robots tr[data-robot='el-e-1'][data-online=yes]").await;
    assert!(row.text().await.unwrap().contains("free: nothing it can do is waiting"));
    page.close().await;
}

#[tokio::test]
async fn a_caretaker_sees_a_robots_decline_and_why_the_task_waits() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let bedside = "E2003412000000000000BED1";
    fixtures::copy_tag(&registry, "355AB1C60000003000000001", bedside, "Bedside lamp").await;
    let token = fixtures::robot(&registry, "stretch-1", "stretch").await;
    let _robot = WorkingRobot::start(&registry, "stretch-1", &token);

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open("/#/tasks").await;
    page.wait_for_text("main", "Nobody asked for anything yet").await;
    let body = json!({ "epc": bedside, "action": "off" });
    let (status, task) =
        registry.call(Method::POST, "/api/v1/tasks", &registry.admin_token, Some(&body), &[]).await;
    assert_eq!(status, StatusCode::CREATED, "{task}");
    let asked_at = Instant::now();

    let row = format!("table.tasks tr[data-task='{}']", task["id"].as_str().unwrap());
    let stuck =
        page.wait_for_text(&format!("{row} .stuck"), "no device in its simulated room").await;
    assert_eq!(
        stuck.text().await.unwrap(),
        "Why it waits: stretch-1 declined: no device in its simulated room has this tag; no other \
         robot can do it. It stays waiting until a robot can take it; cancel it if it is no \
         longer wanted."
    );
    assert!(asked_at.elapsed() < Duration::from_secs(10), "seen in {:?}", asked_at.elapsed());
    // The red note gives the reason; the list under it says who declined and when, once.
    let decline = page.wait_for(&format!("{row} .declines li")).await.text().await.unwrap();
    assert!(decline.starts_with("stretch-1 declined ("), "{decline}");
    // On a phone the note takes the card's width under its label, not a column beside it.
    let share = page
        .eval(&format!(
            "const note = document.querySelector(\"{row} .stuck\").getBoundingClientRect();
             const card = document.querySelector(\"{row}\").getBoundingClientRect();
             return note.width / card.width"
        ))
        .await;
    assert!(share.as_f64().unwrap() > 0.85, "the note is {share} of the card's width");
    assert!(page.fits_width().await, "the tasks page fits a phone");
    assert_eq!(page.accessibility_problems().await, Vec::<String>::new());
    page.close().await;
}

#[tokio::test]
async fn the_robots_own_words_open_on_request_and_a_long_reason_leaves_the_row_readable() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let token = fixtures::robot(&registry, "stretch-1", "stretch").await;
    let body = json!({ "epc": ADA_SWITCH, "action": "off", "note": "before bed" });
    let (status, task) =
        registry.call(Method::POST, "/api/v1/tasks", &registry.admin_token, Some(&body), &[]).await;
    assert_eq!(status, StatusCode::CREATED, "{task}");
    let id = task["id"].as_str().unwrap();
    let reason = "it tried and could not find the tag: something red larger than any tag of \
                  this home is where you pointed, and the tag could not be told apart from it; \
                  move the red thing away from the tag, or point at the middle of the tag";
    let said = "no tag taken near the pointed location: the red region nearest the target \
                (2137 points, 3 cm from it) is 35 cm across, larger than any tag (17 cm at \
                most), and neither its colours, its surfaces nor its shape divide it";
    let decline = json!({ "reason": reason, "detail": said });
    let path = format!("/api/v1/tasks/{id}/decline");
    let (status, declined) = registry.call(Method::POST, &path, &token, Some(&decline), &[]).await;
    assert_eq!(status, StatusCode::OK, "{declined}");

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, DESKTOP).await;
    page.log_in("anna", PASSWORD).await;
    page.open("/#/tasks").await;
    let row = format!("table.tasks tr[data-task='{id}']");
    let stuck = page.wait_for(&format!("{row} .stuck")).await.text().await.unwrap();
    assert!(stuck.contains(reason), "{stuck}");
    assert!(!stuck.contains("2137 points"), "the robot's own words wait to be asked for: {stuck}");

    let words = format!("{row} details.robot-words");
    let open = format!("return document.querySelector(\"{words}\").open");
    assert_eq!(page.eval(&open).await, false, "the robot's own words wait to be asked for");
    let row_text = page.wait_for(&row).await.text().await.unwrap();
    assert!(!row_text.contains("2137 points"), "{row_text}");
    page.click(&format!("{words} summary")).await;
    assert_eq!(page.eval(&open).await, true);
    let opened = page.wait_for(&format!("{words} p")).await.text().await.unwrap();
    assert_eq!(opened, said);

    // Beside a long reason the short columns keep every word whole: a column squeezed to a few
    // letters breaks its words into more lines than it has words.
    let broken = page
        .eval(&format!(
            "return [...document.querySelectorAll(\"{row} td:not([data-label=State]) .cell\")]
               .flatMap((cell) => [...cell.querySelectorAll('a, strong, div, button')])
               .filter((element) => element.children.length === 0 && element.textContent.trim())
               .filter((element) => {{
                 const range = document.createRange();
                 range.selectNodeContents(element);
                 const lines = new Set([...range.getClientRects()].map((r) => Math.round(r.top)));
                 return lines.size > element.textContent.trim().split(/\\s+/).length;
               }})
               .map((element) => element.textContent)"
        ))
        .await;
    assert_eq!(broken, json!([]), "words broken apart in the short columns");
    assert!(page.fits_width().await, "the tasks page fits a desktop");
    assert_eq!(page.accessibility_problems().await, Vec::<String>::new());
    page.close().await;
}

#[tokio::test]
async fn an_admin_adds_a_robot_and_sees_its_token_once() {
    let registry = Registry::start();
    registry.add_user("root", "admin", PASSWORD);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("root", PASSWORD).await;
    page.open("/#/admin").await;
    page.fill("input[name=robot-id]", "stretch-2").await;
    page.fill("input[name=robot-class]", "stretch").await;
    // What a robot can do reads as the schema titles it, as on every other page.
    let labels = page
        .eval("return [...document.querySelectorAll('input[name=capability]')].map((box) => `${box.value}: ${box.labels[0].textContent}`)")
        .await;
    assert_eq!(
        labels,
        json!([
            "light_switch: Operate a light switch",
            "pull_back: Pull back (to open)",
            "push: Push (to close)",
            "pull_lamp: Pull a lamp's chain",
            "drop: Drop an object in"
        ])
    );
    page.click("input[name=capability][value=drop]").await;
    page.click_text("form.add-robot button", "Add robot").await;
    page.wait_for_text("main .status", "Added stretch-2").await;
    let token = page.eval("return document.querySelector('#robot-token input').value").await;
    let token = token.as_str().unwrap();

    let robot = registry.get("/api/v1/robots/stretch-2").await;
    assert_eq!(robot["class"], "stretch");
    assert_eq!(robot["capabilities"], json!(["light_switch", "pull_back", "push", "pull_lamp"]));
    let claim = registry
        .request(Method::POST, "/api/v1/robots/stretch-2/tasks/claim", token)
        .send()
        .await
        .unwrap();
    assert_eq!(claim.status(), StatusCode::NO_CONTENT, "the token shown works as stretch-2");
    assert!(page.fits_width().await, "the admin page fits a phone");
    page.close().await;
}

#[tokio::test]
async fn a_task_nobody_did_in_time_reads_as_expired_on_the_tasks_page() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open("/#/tasks").await;
    page.wait_for_text("main", "Nobody asked for anything yet").await;
    let soon = time::OffsetDateTime::now_utc() + time::Duration::seconds(2);
    let soon = soon.format(&time::format_description::well_known::Rfc3339).unwrap();
    let body = json!({ "epc": ADA_SWITCH, "action": "off", "expires_at": soon });
    let (status, task) =
        registry.call(Method::POST, "/api/v1/tasks", &registry.admin_token, Some(&body), &[]).await;
    assert_eq!(status, StatusCode::CREATED, "{task}");

    let row = format!("table.tasks tr[data-task='{}']", task["id"].as_str().unwrap());
    page.wait_for_text(&format!("{row}[data-expired=no]"), "Expires").await;
    let expired = page.wait_for(&format!("{row}[data-expired=yes] .expired")).await;
    let words = expired.text().await.unwrap();
    assert!(words.starts_with("No robot took it before it expired ("), "{words}");
    assert!(words.ends_with("Ask again if it is still wanted."), "{words}");
    let state = page.wait_for(&format!("{row} .badge")).await.text().await.unwrap();
    assert_eq!(state, "expired");
    assert_eq!(page.accessibility_problems().await, Vec::<String>::new());
    page.close().await;
}
