//! Experiments apart, as a caretaker sees them: the tag page's success rate counts real use,
//! says so in words, and counts experiments and tests only when asked, remembering the choice.

use pps_test_kit::{DRAWER, Registry};
use pps_tests::Browser;
use pps_tests::browser::PHONE;
use reqwest::Method;
use serde_json::{Value, json};

const PASSWORD: &str = "correct horse battery";

fn trial(n: u8, outcome: &str, purpose: &str) -> Value {
    json!({
        "id": format!("6f9b1d2e-8c4a-4b7e-9f10-3a2b1c0d9e{n:02x}"), "epc": DRAWER,
        "robot": "el-e-1", "action": "open", "behavior": "pull_open",
        "started_at": format!("2026-03-01T10:{n:02}:00Z"),
        "finished_at": format!("2026-03-01T10:{n:02}:40Z"),
        "outcome": outcome, "purpose": purpose,
    })
}

#[tokio::test]
async fn an_experiments_failures_stay_out_of_the_success_rate_until_asked_for() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let robot = registry.token("robot", "el-e-1");
    let trials = [
        trial(1, "success", "use"),
        trial(2, "success", "use"),
        trial(3, "failure", "experiment"),
        trial(4, "failure", "experiment"),
        trial(5, "failure", "experiment"),
    ];
    for trial in &trials {
        let path = format!("/api/v1/trials/{}", trial["id"].as_str().unwrap());
        let (status, body) = registry.call(Method::PUT, &path, &robot, Some(trial), &[]).await;
        assert!(status.is_success(), "the robot recorded its trial: {status} {body}");
    }
    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open(&format!("/#/tags/{DRAWER}")).await;

    page.wait_for_text(".counted", "Real use only; 3 experiment trials not counted.").await;
    let open = ".rates li[data-action=open]";
    page.wait_for_text(&format!("{open} .rate"), "100 %").await;
    page.wait_for_text(open, "of 2 tries").await;
    let experiment = page.wait_for_text("#trials tr[data-trial$='9e03']", "Experiment").await;
    assert!(experiment.text().await.unwrap().contains("Did not work"));
    let real_use = page.wait_for("#trials tr[data-trial$='9e01']").await;
    assert!(!real_use.text().await.unwrap().contains("Experiment"));

    page.click_text("label", "Include experiments and tests").await;
    page.wait_for_text(".counted", "Counting real use, experiments and tests.").await;
    page.wait_for_text(&format!("{open} .rate"), "40 %").await;
    page.wait_for_text(open, "of 5 tries").await;

    // The choice is anna's until she changes it: it holds on her next visit.
    page.open("/#/tags").await;
    page.open(&format!("/#/tags/{DRAWER}")).await;
    page.wait_for_text(".counted", "Counting real use, experiments and tests.").await;
    page.wait_for_text(&format!("{open} .rate"), "40 %").await;
    page.click_text("label", "Include experiments and tests").await;
    page.wait_for_text(".counted", "Real use only; 3 experiment trials not counted.").await;
    page.close().await;
}
