//! Every page of the caretakers' UI holds up to axe-core (from npm, injected into Chromium): no
//! serious or critical violation, on a phone-wide screen, with content in every table.

use pps_test_kit::Registry;
use pps_test_kit::fixtures::{self, ADA_SWITCH};
use pps_tests::Browser;
use pps_tests::browser::PHONE;
use reqwest::{Method, StatusCode};
use serde_json::json;

const PASSWORD: &str = "correct horse battery";

#[tokio::test]
async fn every_page_passes_axe_core_without_serious_violations() {
    let registry = Registry::start();
    registry.add_user("ada", "admin", PASSWORD);
    let robot = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let (status, _) =
        fixtures::put_trial(&registry, &robot, &fixtures::switch_trial("el-e-1")).await;
    assert_eq!(status, StatusCode::CREATED);
    let ask = json!({ "epc": ADA_SWITCH, "action": "off", "note": "hallway, please" });
    let (status, _) =
        registry.call(Method::POST, "/api/v1/tasks", &registry.admin_token, Some(&ask), &[]).await;
    assert_eq!(status, StatusCode::CREATED);

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    let mut problems = Vec::new();
    page.open("/").await;
    page.wait_for("input[name=username]").await;
    problems.extend(page.accessibility_problems().await.into_iter().map(|p| format!("login: {p}")));
    page.log_in("ada", PASSWORD).await;
    // The checker itself: an unlabelled field is a critical violation it must see.
    page.eval("document.body.append(Object.assign(document.createElement('input'), { id: 'probe' })); return null").await;
    let seen = page.accessibility_problems().await;
    assert!(
        seen.iter().any(|p| p.contains("label")),
        "axe-core missed an unlabelled field: {seen:?}"
    );
    page.eval("document.getElementById('probe').remove(); return null").await;

    // Each page, and what shows that it has rendered its content.
    let pages = [
        ("#/tags", "table.tags"),
        (&*format!("#/tags/{ADA_SWITCH}"), "table.trials"),
        (&*format!("#/tags/{ADA_SWITCH}/edit"), "[data-focus-key='/properties/name']"),
        ("#/register", "button.template"),
        ("#/tasks", "table.tasks"),
        ("#/robots", "table.robots"),
        ("#/admin", "main h1"),
        ("#/account", "main h1"),
    ];
    for (hash, ready) in pages {
        page.open(&format!("/{hash}")).await;
        page.wait_for(ready).await;
        let found = page.accessibility_problems().await;
        problems.extend(found.into_iter().map(|p| format!("{hash}: {p}")));
    }
    // The ask form, opened.
    page.open(&format!("/#/tags/{ADA_SWITCH}")).await;
    page.click("button.ask[data-action=off]").await;
    page.wait_for("form.ask-form select").await;
    let found = page.accessibility_problems().await;
    problems.extend(found.into_iter().map(|p| format!("ask form: {p}")));
    // The advanced section, opened, and the register form of one kind of device.
    page.open(&format!("/#/tags/{ADA_SWITCH}")).await;
    page.click("details.advanced > summary").await;
    page.wait_for_text("details.advanced", "push_top").await;
    let found = page.accessibility_problems().await;
    problems.extend(found.into_iter().map(|p| format!("advanced section: {p}")));
    page.open("/#/register").await;
    page.click("button.template[data-template='lamp']").await;
    page.wait_for("[data-focus-key='/properties/name']").await;
    let found = page.accessibility_problems().await;
    problems.extend(found.into_iter().map(|p| format!("register form: {p}")));
    assert!(problems.is_empty(), "axe-core found:\n{}", problems.join("\n"));
    page.close().await;
}
