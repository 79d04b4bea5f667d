//! The caretakers' UI in a real browser: headless Chromium against the real `pps-server`
//! process, as a caretaker would use it on a phone or a laptop.

use pps_test_kit::{ADA_SWITCH, DRAWER, Registry, wait};
use pps_tests::browser::{DESKTOP, PHONE};
use pps_tests::{Browser, Session};
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

const PASSWORD: &str = "correct horse battery";
const LAMP: &str = "355AB1C60000003000000001";
const TRASH_CAN: &str = "355AB1C60000005000000001";

/// A registry with one caretaker login, and a browser to use it.
async fn caretaker_at(size: (u32, u32)) -> (Registry, Browser, Session) {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, size).await;
    page.log_in("anna", PASSWORD).await;
    (registry, browser, page)
}

/// The JavaScript that finds the form field the registry's JSON pointer names.
fn field_at(pointer: &str) -> String {
    format!("document.querySelector('[data-focus-key=\"{pointer}\"]').closest('.field')")
}

fn trial(id: &str, epc: &str, outcome: &str) -> Value {
    json!({
        "id": id, "epc": epc, "robot": "el-e-1", "action": "open", "behavior": "pull_open",
        "started_at": "2026-03-01T10:00:00Z", "finished_at": "2026-03-01T10:00:40Z",
        "outcome": outcome, "detector": { "displacement_m": 0.29 }, "forces": [],
        "measurements": { "pull_distance": 0.29 },
    })
}

#[tokio::test]
async fn logging_in_with_enter_after_a_wrong_password_and_out_again() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    assert_eq!(page.eval("return window.innerWidth").await, 375, "a phone-wide viewport");
    page.open("/").await;
    let username = page.wait_for("input[name=username]").await;
    assert_eq!(username.attr("autocomplete").await.unwrap().as_deref(), Some("username"));
    page.fill("input[name=username]", "anna").await;
    page.fill("input[name=password]", "wrong password\u{E007}").await;
    page.wait_for_text(".login-form .status", "Wrong user name or password").await;

    page.log_in("Anna", PASSWORD).await;
    page.wait_for_text("table.tags", "A D A light switch 1").await;
    page.wait_for_text(".who", "anna (caretaker)").await;
    assert!(page.fits_width().await, "the tag list fits a phone");

    page.click_text("button", "Log out").await;
    page.wait_for("input[name=username]").await;
    page.open("/#/tags").await;
    page.wait_for("input[name=username]").await;
    page.close().await;
}

#[tokio::test]
async fn registering_a_tag_from_a_template_and_fixing_the_field_the_registry_flags() {
    let (registry, _browser, page) = caretaker_at(DESKTOP).await;
    // A robot read the new tag before anyone registered it: it waits in the inbox.
    let epc = "E20034120000000000009001";
    let robot = registry.token("robot", "el-e-1");
    let read = format!("/api/v1/robots/el-e-1/tags/{epc}");
    let (status, _) = registry.call(Method::GET, &read, &robot, None, &[]).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    wait::until("the inbox to list the unknown EPC", || async {
        registry.get("/api/v1/inbox").await.to_string().contains(epc).then_some(())
    })
    .await;

    page.click("a[data-nav=register]").await;
    page.click(&format!(".inbox button[data-epc='{epc}']")).await;
    page.click("button.template[data-template='ada light switch']").await;
    // Behaviour parameters are for robot engineers: behind the advanced section.
    page.click("details.advanced > summary").await;
    let epc_field = page.wait_for("input[name=epc]").await;
    assert_eq!(epc_field.prop("value").await.unwrap().as_deref(), Some(epc), "one click filled it");
    page.fill("[data-focus-key='/properties/name']", "Hall switch").await;
    page.fill("[data-focus-key='/properties/location/room']", "hallway").await;
    let force = "/behaviors/push_top/force_threshold";
    page.fill(&format!("[data-focus-key='{force}']"), "500").await;

    // The registry's error lands at the field its JSON pointer names, as the caretaker types.
    let error = format!("{}.querySelector('.field-error')", field_at(force));
    page.wait_until(
        "the force error at its field",
        &format!("!{error}.hidden && {error}.textContent.includes('20')"),
    )
    .await;
    let invalid = format!(
        "{}.querySelector('input').getAttribute('aria-invalid') === 'true'",
        field_at(force)
    );
    assert_eq!(page.eval(&format!("return {invalid}")).await, true);
    let elsewhere = "[...document.querySelectorAll('.field-error')].filter(e => !e.hidden).length";
    assert_eq!(page.eval(&format!("return {elsewhere}")).await, 1, "only that field is flagged");

    page.fill(&format!("[data-focus-key='{force}']"), "4").await;
    page.wait_until("the error to clear", &format!("{error}.hidden")).await;
    page.wait_for_text(".save-bar .status", "No problems found").await;

    // A tag size begun and cleared again is left out, not asked to be finished.
    let width = "[data-focus-key='/properties/tag_size/width']";
    let height = "[data-focus-key='/properties/tag_size/height']";
    page.fill(width, "0.05").await;
    page.wait_until(
        "the half-given size to be missing its height",
        "document.querySelector('.save-bar .status').textContent.includes('Still to fill in')",
    )
    .await;
    page.wait_for(width).await.send_keys("\u{E003}\u{E003}\u{E003}\u{E003}").await.expect("erased");
    page.wait_for_text(".save-bar .status", "No problems found").await;
    page.fill(width, "0.05").await;
    page.fill(height, "0.08").await;
    page.wait_for_text(".save-bar .status", "No problems found").await;
    page.screenshot_full_page("register-advanced-desktop").await;
    page.set_viewport(PHONE).await;
    page.screenshot_full_page("register-advanced-phone").await;
    assert!(page.fits_width().await, "the advanced form scrolls sideways on a phone");
    page.set_viewport(DESKTOP).await;
    page.click_text("button", "Register tag").await;
    page.wait_for_text("h1.tag-title", "Hall switch").await;

    let stored = registry.get(&format!("/api/v1/tags/{epc}")).await;
    assert_eq!(stored["behaviors"]["push_top"]["force_threshold"], 4.0);
    assert_eq!(stored["properties"]["type"], "ada light switch");
    assert_eq!(stored["properties"]["location"]["room"], "hallway");
    assert_eq!(
        stored["properties"]["tag_size"],
        serde_json::json!({"width": 0.05, "height": 0.08})
    );
    assert_eq!(stored["updated_by"], "anna");
    page.close().await;
}

#[tokio::test]
async fn the_second_of_two_caretakers_saving_the_same_tag_sees_the_conflict() {
    let (registry, browser, anna) = caretaker_at(DESKTOP).await;
    registry.add_user("bert", "caretaker", PASSWORD);
    let bert = browser.session(&registry.url, DESKTOP).await;
    bert.log_in("bert", PASSWORD).await;
    for page in [&anna, &bert] {
        page.open(&format!("/#/tags/{DRAWER}/edit")).await;
        page.wait_for_text(".save-bar .status", "No problems found").await;
    }
    anna.fill("[data-focus-key='/properties/name']", "kitchen drawer").await;
    anna.click_text("button", "Save changes").await;
    anna.wait_for_text("h1.tag-title", "kitchen drawer").await;

    bert.fill("[data-focus-key='/properties/location/room']", "pantry").await;
    bert.click_text("button", "Save changes").await;
    bert.wait_for_text(".conflict h2", "Someone else saved this tag first").await;
    bert.wait_for_text(".conflict tr[data-pointer='/properties/name']", "kitchen drawer").await;
    bert.wait_for_text(".conflict tr[data-pointer='/properties/location/room']", "pantry").await;
    bert.screenshot("conflict-desktop").await;
    let unchanged = registry.get(&format!("/api/v1/tags/{DRAWER}")).await;
    assert_eq!(unchanged["properties"]["location"]["room"], "kitchen", "nothing was overwritten");

    bert.click_text(".conflict button", "Reapply my changes").await;
    bert.wait_for_text(".save-bar .status", "review them and save").await;
    bert.click_text("button", "Save changes").await;
    bert.wait_for_text("h1.tag-title", "kitchen drawer").await;
    let merged = registry.get(&format!("/api/v1/tags/{DRAWER}")).await;
    assert_eq!(merged["properties"]["name"], "kitchen drawer");
    assert_eq!(merged["properties"]["location"]["room"], "pantry");
    assert_eq!(merged["revision"], 3);
    assert_eq!(merged["updated_by"], "bert");
    anna.close().await;
    bert.close().await;
}

#[tokio::test]
async fn a_trial_a_robot_records_appears_on_the_tag_page_without_a_reload() {
    let (registry, _browser, page) = caretaker_at(PHONE).await;
    let robot = registry.token("robot", "el-e-1");
    page.open(&format!("/#/tags/{DRAWER}")).await;
    page.wait_for_text("#trials", "No robot has tried this tag yet").await;
    page.eval("window.stillTheSamePage = true; return null").await;

    let id = "6f9b1d2e-8c4a-4b7e-9f10-3a2b1c0d9e8f";
    let (status, body) = registry
        .call(
            Method::PUT,
            &format!("/api/v1/trials/{id}"),
            &robot,
            Some(&trial(id, DRAWER, "success")),
            &[],
        )
        .await;
    assert!(status.is_success(), "the robot recorded its trial: {status} {body}");
    let row = page.wait_for(&format!("#trials tr[data-trial='{id}']")).await;
    let text = row.text().await.unwrap();
    assert!(text.contains("el-e-1") && text.contains("Worked"), "{text}");
    assert_eq!(page.eval("return window.stillTheSamePage === true").await, true, "no reload");

    // The caretaker's verdict goes back to the registry.
    page.click_text(&format!("#trials tr[data-trial='{id}'] button"), "It worked").await;
    page.wait_gone(&format!("#trials tr[data-trial='{id}'] button"), "It worked").await;
    let stored = registry.get(&format!("/api/v1/trials/{id}")).await;
    assert_eq!(stored["confirmed"], true);
    page.close().await;
}

#[tokio::test]
async fn a_tag_named_with_html_shows_that_text_and_runs_nothing() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let name = "<img src=x onerror=alert(1)>";
    let epc = "E20034120000000000006666";
    let mut entry: Value = registry.get(&format!("/api/v1/tags/{ADA_SWITCH}")).await;
    for key in ["epc_uri", "revision", "updated_at", "updated_by", "archived"] {
        entry.as_object_mut().unwrap().remove(key);
    }
    entry["epc"] = epc.into();
    entry["properties"]["name"] = name.into();
    entry["properties"]["location"]["room"] = "<script>alert(2)</script>".into();
    let (status, _) = registry
        .call(
            Method::PUT,
            &format!("/api/v1/tags/{epc}"),
            &registry.admin_token,
            Some(&entry),
            &[("if-none-match", "*")],
        )
        .await;
    assert_eq!(status, StatusCode::CREATED);

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, DESKTOP).await;
    page.log_in("anna", PASSWORD).await;
    page.fill("input[type=search]", "<img").await;
    // The search narrows the list to that one tag (names are searched as text, not markup).
    page.wait_for_text("main > .status", "1 tag.").await;
    let link = page.wait_for_text("table.tags a.tag-name", "onerror").await;
    assert_eq!(link.text().await.unwrap(), name);
    page.wait_for_text("table.tags", "<script>alert(2)</script>").await;
    link.click().await.unwrap();
    let title = page.wait_for_text("h1.tag-title", "onerror").await;
    assert_eq!(title.text().await.unwrap(), name);
    assert_eq!(
        page.eval("return document.querySelectorAll('img, script:not([src])').length").await,
        0
    );
    assert!(page.client.get_alert_text().await.is_err(), "no script ran");
    page.close().await;
}

#[tokio::test]
async fn archiving_asks_first_restoring_brings_it_back_and_a_worn_tag_moves_to_a_new_epc() {
    let (registry, _browser, page) = caretaker_at(PHONE).await;
    page.open(&format!("/#/tags/{LAMP}")).await;
    page.click_text(".tag-head button", "Archive").await;
    page.click_text("dialog button", "Cancel").await;
    assert_eq!(registry.get(&format!("/api/v1/tags/{LAMP}")).await["archived"], false);
    page.click_text(".tag-head button", "Archive").await;
    page.click_text("dialog button", "Archive").await;
    page.wait_for_text(".banner", "This tag is archived").await;
    assert_eq!(registry.get(&format!("/api/v1/tags/{LAMP}")).await["archived"], true);

    page.open("/#/tags").await;
    page.wait_gone("table.tags", "lamp 1").await;
    page.click("input[type=checkbox]").await;
    page.click_text(&format!("tr[data-epc='{LAMP}'] button"), "Restore").await;
    page.wait_for_text("main > .status", "Restored").await;
    let restored = registry.get(&format!("/api/v1/tags/{LAMP}")).await;
    assert_eq!(
        (restored["archived"].as_bool(), restored["revision"].as_i64()),
        (Some(false), Some(3))
    );

    let new_epc = "E20034120000000000005555";
    page.open(&format!("/#/tags/{TRASH_CAN}")).await;
    page.click("details.advanced > summary").await;
    page.click_text("details.retag summary", "Replace a worn tag").await;
    page.fill("details.retag input", new_epc).await;
    page.click_text("details.retag button", "Move to new EPC").await;
    page.click_text("dialog button", "Move it").await;
    page.wait_until("the page of the new EPC", &format!("location.hash.endsWith('{new_epc}')"))
        .await;
    page.wait_for_text("h1.tag-title", "trash can 1").await;
    assert_eq!(
        registry.get(&format!("/api/v1/tags/{new_epc}")).await["properties"]["type"],
        "trash can"
    );
    page.close().await;
}

#[tokio::test]
async fn an_admin_adds_a_login_and_mints_a_token_shown_only_once() {
    let registry = Registry::start();
    registry.add_user("root", "admin", PASSWORD);
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, DESKTOP).await;
    page.log_in("root", PASSWORD).await;
    page.click("a[data-nav=admin]").await;
    page.fill("input[name=new-user-name]", "Bert").await;
    page.fill("input[name=new-user-password]", "bert's password").await;
    page.click_text("button", "Add user").await;
    page.wait_for_text("table.users tr[data-user=bert]", "caretaker").await;
    let bert = browser.session(&registry.url, PHONE).await;
    bert.log_in("bert", "bert's password").await;
    bert.close().await;

    page.fill("input[name=token-name]", "el-e-2").await;
    page.fill("input[name=token-days]", "30").await;
    page.click_text("button", "Create token").await;
    let secret = page.wait_for("input.secret").await;
    let token = secret.prop("value").await.unwrap().unwrap_or_default();
    assert!(token.starts_with("pps_"), "{token}");
    let (status, _) = registry.call(Method::GET, "/api/v1/tags", &token, None, &[]).await;
    assert_eq!(status, StatusCode::OK, "the token shown works");
    page.wait_for_text("table.tokens", "el-e-2").await;

    page.click_text("table.tokens tr:last-child button", "Revoke").await;
    page.click_text("dialog button", "Revoke").await;
    page.wait_for_text("table.tokens tr:last-child", "revoked").await;
    page.open("/#/robots").await;
    page.open("/#/admin").await;
    page.wait_for_text("table.tokens", "el-e-2").await;
    assert_eq!(
        page.eval("return document.querySelectorAll('input.secret').length").await,
        0,
        "shown once"
    );
    page.close().await;
}

/// Opens a page, waits for what shows it is ready, checks it fits and saves a screenshot.
async fn capture(page: &Session, path: &str, ready: (&str, &str), name: &str, width: &str) {
    page.open(path).await;
    page.wait_for_text(ready.0, ready.1).await;
    if width == "phone" {
        assert!(page.fits_width().await, "{name} scrolls sideways on a phone");
    }
    page.screenshot_full_page(&format!("{name}-{width}")).await;
}

#[tokio::test]
async fn every_main_page_fits_a_phone_and_a_desktop_and_is_captured() {
    let registry = Registry::start();
    registry.add_user("root", "admin", PASSWORD);
    let robot = registry.token("robot", "el-e-1");
    let admin = registry.admin_token.clone();
    let el_e = json!({
        "id": "el-e-1", "class": "el-e", "name": "EL-E",
        "capabilities": ["light_switch", "pull_back", "push", "pull_lamp", "drop"], "limits": { "max_force": 15.0 },
    });
    let (status, body) =
        registry.call(Method::PUT, "/api/v1/robots/el-e-1", &admin, Some(&el_e), &[]).await;
    assert!(status.is_success(), "robot registered: {status} {body}");
    for (i, outcome) in ["success", "success", "failure"].iter().enumerate() {
        let id = format!("00000000-0000-4000-8000-00000000000{i}");
        let (status, body) = registry
            .call(
                Method::PUT,
                &format!("/api/v1/trials/{id}"),
                &robot,
                Some(&trial(&id, DRAWER, outcome)),
                &[],
            )
            .await;
        assert!(status.is_success(), "trial recorded: {status} {body}");
    }

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    for (size, width) in [(PHONE, "phone"), (DESKTOP, "desktop")] {
        page.set_viewport(size).await;
        page.open("/").await;
        page.wait_for("input[name=username]").await;
        page.screenshot_full_page(&format!("login-{width}")).await;
        page.log_in("root", PASSWORD).await;
        capture(&page, "/#/tags", ("table.tags", "drawer 1"), "tags", width).await;
        capture(&page, &format!("/#/tags/{DRAWER}"), ("#trials", "EL-E"), "tag", width).await;
        page.open("/#/register").await;
        page.click("button.template[data-template='drawer']").await;
        page.wait_for_text(".save-bar .status", "Still to fill in").await;
        page.screenshot_full_page(&format!("register-{width}")).await;
        if width == "phone" {
            assert!(page.fits_width().await, "the register form scrolls sideways on a phone");
        }
        capture(&page, "/#/robots", ("table.robots", "EL-E"), "robots", width).await;
        capture(&page, "/#/admin", ("table.tokens", "first admin"), "admin", width).await;
        page.click_text("button", "Log out").await;
        page.wait_for("input[name=username]").await;
    }
    page.close().await;
}
