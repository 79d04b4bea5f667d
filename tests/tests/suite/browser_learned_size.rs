//! The size the robots learned a tag to have, on its page in a caretaker's words (issue 34),
//! and the registered size named as the one robots use once a caretaker gives it, on the page
//! and in what the page says each robot gets.

use pps_test_kit::{DRAWER, Registry};
use pps_tests::Browser;
use pps_tests::browser::{DESKTOP, PHONE};
use reqwest::Method;
use serde_json::json;

const PASSWORD: &str = "correct horse battery";

#[tokio::test]
async fn a_size_the_robots_learned_shows_on_the_tag_page_in_centimetres() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", PASSWORD);
    let robot = registry.token("robot", "el-e-1");
    let admin = registry.admin_token.clone();
    let el_e =
        json!({ "id": "el-e-1", "class": "el-e", "name": "EL-E", "capabilities": ["pull_back"] });
    let (status, body) =
        registry.call(Method::PUT, "/api/v1/robots/el-e-1", &admin, Some(&el_e), &[]).await;
    assert!(status.is_success(), "robot registered: {status} {body}");
    for (n, (width, height)) in [(0.158, 0.236), (0.163, 0.241), (0.171, 0.239)].iter().enumerate()
    {
        let id = format!("5112e000-0000-4000-8000-00000000000{n}");
        let trial = json!({
            "id": id, "epc": DRAWER, "robot": "el-e-1", "action": "open", "behavior": "pull_open",
            "started_at": "2026-03-01T10:00:00Z", "finished_at": "2026-03-01T10:00:40Z",
            "outcome": "success", "confirmed": true, "detector": {}, "forces": [],
            "measurements": {}, "tag_size": { "width": width, "height": height },
        });
        let path = format!("/api/v1/trials/{id}");
        let (status, body) = registry.call(Method::PUT, &path, &robot, Some(&trial), &[]).await;
        assert!(status.is_success(), "the robot recorded its trial: {status} {body}");
    }

    let browser = Browser::start().await;
    let page = browser.session(&registry.url, PHONE).await;
    page.log_in("anna", PASSWORD).await;
    page.open(&format!("/#/tags/{DRAWER}")).await;
    page.click("details.advanced > summary").await;
    let said = page.wait_for_text("p.learned-size", "Seen by the robots").await;
    assert_eq!(
        said.text().await.unwrap(),
        "Seen by the robots: about 16 × 24 cm, from 3 confirmed visits. Robots use it until a \
         size is registered for the tag."
    );
    let size_row = "tr[data-pointer='/properties/tag_size/width']";
    let row = page.wait_for_text(size_row, "learned").await;
    assert!(row.text().await.unwrap().contains("0.163"), "the robot gets the median width");
    page.screenshot_full_page("tag-learned-size-phone").await;

    let mut entry = registry.get(&format!("/api/v1/tags/{DRAWER}")).await;
    entry["properties"]["tag_size"] = json!({ "width": 0.15, "height": 0.25 });
    let revision = format!("\"r{}\"", entry["revision"]);
    let path = format!("/api/v1/tags/{DRAWER}");
    let (status, body) =
        registry.call(Method::PUT, &path, &admin, Some(&entry), &[("if-match", &revision)]).await;
    assert!(status.is_success(), "the caretaker's size was saved: {status} {body}");
    // The page hears of the change and says which size robots now use, without a reload.
    page.wait_for_text("p.learned-size", "robots use the size registered for it, 15 × 25 cm").await;
    // And what the robot gets is the caretaker's size: no longer a learned value on its row.
    page.wait_gone(size_row, "learned").await;
    page.set_viewport(DESKTOP).await;
    page.screenshot_full_page("tag-learned-size-desktop").await;
    page.close().await;
}
