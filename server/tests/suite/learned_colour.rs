//! Colour learned from confirmed reads (DESIGN §10): the trials' `tag_color` teach each tag's
//! colour and the household's for the robot class, which the effective entries carry beside the
//! entry's own `color_segmentation`, with provenance `learned`.

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::StatusCode;
use serde_json::{Value, json};

/// A look at the red towel as a flash camera sees it, its median hue `hue` degrees.
fn towel(hue: f64) -> Value {
    json!({
        "pixels": 420,
        "hue_deg": [(hue - 5.0f64).rem_euclid(360.0), hue, (hue + 5.0f64).rem_euclid(360.0)],
        "saturation": [0.78, 0.86, 0.93],
        "value": [0.35, 0.55, 0.7],
        "light_level": 0.42
    })
}

#[tokio::test]
async fn three_reads_teach_the_tag_and_the_household_their_colour() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let drawer = format!("/api/v1/robots/el-e-1/tags/{DRAWER}");
    let switch = format!("/api/v1/robots/el-e-1/tags/{ADA_SWITCH}");
    let send = |hue: f64, purpose: &'static str| {
        let (server, robot) = (&server, robot.clone());
        async move {
            let id = uuid();
            let mut body = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "success");
            body["tag_color"] = towel(hue);
            body["purpose"] = json!(purpose);
            let sent = server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await;
            assert_eq!(sent.status(), StatusCode::CREATED);
        }
    };
    // An experiment's reads, and two real ones, are not enough to learn from.
    for hue in [20.0, 25.0, 30.0] {
        send(hue, "experiment").await;
    }
    send(358.0, "use").await;
    send(2.0, "use").await;
    let entry: Value = server.get(&drawer, &robot).await.json().await.unwrap();
    assert!(entry["entry"]["properties"].get("learned_color_segmentation").is_none(), "{entry}");

    send(0.0, "use").await;
    let entry: Value = server.get(&drawer, &robot).await.json().await.unwrap();
    let properties = &entry["entry"]["properties"];
    let learned = &properties["learned_color_segmentation"];
    assert_eq!(learned["trials"], 3);
    let [from, to] =
        [learned["hue_deg"][0].as_f64().unwrap(), learned["hue_deg"][1].as_f64().unwrap()];
    // Every look's 5th to 95th percentile, 353..7°, widened by how far the medians differ (1.6°).
    assert!((351.0..353.0).contains(&from) && (7.0..9.0).contains(&to), "{learned}");
    assert!(to < 14.0, "plywood's hue, 14–24°, is left out");
    assert_eq!(properties["color_segmentation"]["hue_deg"], json!([340, 20]), "the entry's own");
    assert_eq!(entry["provenance"]["/properties/learned_color_segmentation/hue_deg"], "learned");
    assert_eq!(entry["provenance"]["/properties/color_segmentation/hue_deg"], "class:el-e");

    // The household's model reaches every tag of the class, none read yet.
    let other: Value = server.get(&switch, &robot).await.json().await.unwrap();
    assert_eq!(
        other["entry"]["properties"]["household_color_segmentation"],
        properties["household_color_segmentation"]
    );
    assert_eq!(other["entry"]["properties"]["household_color_segmentation"]["trials"], 3);
    assert!(other["entry"]["properties"].get("learned_color_segmentation").is_none());
    assert_eq!(other["provenance"]["/properties/household_color_segmentation/value"], "learned");
}

#[tokio::test]
async fn a_look_out_of_bounds_is_refused_and_teaches_nothing() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let id = uuid();
    let mut body = trial(&id, DRAWER, "el-e-1", "open", "pull_open", "success");
    body["tag_color"] = json!({ "pixels": 3, "hue_deg": [1, 2, 3], "saturation": [0.5, 0.6, 1.7],
        "value": [0.2, 0.3, 0.4], "light_level": 0.5 });
    let refused = server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await;
    assert_eq!(refused.status(), StatusCode::UNPROCESSABLE_ENTITY);
    let problem: Value = refused.json().await.unwrap();
    assert!(problem.to_string().contains("/tag_color/saturation/2"), "{problem}");
}
