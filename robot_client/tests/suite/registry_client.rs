//! The registry client against a real registry: cached entries that follow the change feed,
//! the start-up read of every tag, and trials that survive the registry going away and the
//! robot restarting.

use std::time::Duration;

use pps_robot::registry::{RegistryClient, Source};
use pps_robot::sim::DeviceKind;
use pps_schema::{Epc, RobotId, Trial};
use pps_test_kit::{ADA_SWITCH, Config, RobotRegistry, wait_for, wait_until};
use serde_json::json;

fn trial(robot: &str) -> Trial {
    serde_json::from_value(json!({
        "id": uuid::Uuid::new_v4(), "epc": ADA_SWITCH, "robot": robot, "action": "on",
        "behavior": "push_top", "started_at": "2026-11-22T10:00:00Z",
        "finished_at": "2026-11-22T10:00:30Z", "outcome": "success",
        "detector": { "brightness_change": -0.3 }
    }))
    .unwrap()
}

#[tokio::test]
async fn cached_entries_follow_the_change_feed_and_serve_while_offline() {
    let dir = tempfile::tempdir().unwrap();
    let mut registry = RobotRegistry::start().await;
    let token = registry.robot_token.clone();
    let client = RegistryClient::new(
        &registry.url,
        &token,
        RobotId::parse("el-e-1").unwrap(),
        &dir.path().join("robot"),
    )
    .unwrap();
    let epc = Epc::parse(ADA_SWITCH).unwrap();

    let first = client.effective_entry(&epc).await.unwrap();
    assert_eq!(first.source, Source::Registry);
    assert_eq!(
        client.effective_entry(&epc).await.unwrap().source,
        Source::Revalidated,
        "a 304 without the feed"
    );

    let _watch = client.watch_changes();
    let reason = "the feed to be live, so entries are used without asking";
    wait_for(Duration::from_secs(5), reason, || async {
        client.effective_entry(&epc).await.unwrap().source == Source::Fresh
    })
    .await;

    // A caretaker changes the tag: the feed invalidates the cached entry.
    registry
        .edit_tag(ADA_SWITCH, |entry| {
            entry["behaviors"]["push_top"]["force_threshold"] = json!(4.0);
        })
        .await;
    let updated = wait_until(Duration::from_secs(5), "the change to reach the robot", || async {
        let fetched = client.effective_entry(&epc).await.unwrap();
        (fetched.source == Source::Registry).then_some(fetched)
    })
    .await;
    let threshold = serde_json::to_value(&updated.entry.entry.behaviors["push_top"]).unwrap()["force_threshold"].clone();
    assert_eq!(threshold, json!(4.0));

    // The registry goes away: once the watch has seen the feed drop, the cached entry stands in
    // for it, said to be offline; until then it is served fresh. Never an error.
    registry.stop().await;
    let reason = "the cached entry to stand in, said to be offline";
    wait_for(Duration::from_secs(10), reason, || async {
        client.effective_entry(&epc).await.unwrap().source == Source::Offline
    })
    .await;
    let unknown = Epc::parse("E2003412000000000000AAAA").unwrap();
    assert!(client.effective_entry(&unknown).await.is_err(), "nothing cached, nothing to stand in");
}

#[tokio::test]
async fn trials_recorded_offline_upload_exactly_once_after_a_restart() {
    let dir = tempfile::tempdir().unwrap();
    let mut registry = RobotRegistry::start().await;
    let token = registry.robot_token.clone();
    let state = dir.path().join("robot");
    let robot = RobotId::parse("el-e-1").unwrap();
    let client = RegistryClient::new(&registry.url, &token, robot.clone(), &state).unwrap();

    let online = trial("el-e-1");
    assert_eq!(client.record_trial(&online).await.unwrap().uploaded, 1);

    registry.stop().await;
    let offline: Vec<Trial> = (0..3).map(|_| trial("el-e-1")).collect();
    for trial in &offline {
        let report = client.record_trial(trial).await.unwrap();
        assert_eq!(report.uploaded, 0);
    }
    assert_eq!(client.outbox().len().unwrap(), 3);
    drop(client);

    // The robot restarts (a new client on the same state), then the registry comes back.
    let restarted = RegistryClient::new(&registry.url, &token, robot, &state).unwrap();
    assert_eq!(restarted.outbox().len().unwrap(), 3, "nothing lost across the restart");
    registry.restart().await;
    // One answer was lost on the way back: the registry has it, the outbox does not know.
    let resent = reqwest::Client::new()
        .put(format!("{}/api/v1/trials/{}", registry.url, offline[0].id))
        .bearer_auth(&token)
        .json(&offline[0])
        .send()
        .await
        .unwrap();
    assert_eq!(resent.status(), 201);
    let report = restarted.flush().await.unwrap();
    assert_eq!((report.uploaded, report.already_stored, report.remaining), (2, 1, 0));
    assert!(restarted.outbox().is_empty().unwrap());

    let mut expected: Vec<String> =
        std::iter::once(&online).chain(&offline).map(|t| t.id.to_string()).collect();
    let mut stored: Vec<String> =
        registry.trials().await.iter().map(|t| t["id"].as_str().unwrap().to_owned()).collect();
    expected.sort();
    stored.sort();
    assert_eq!(stored, expected, "each trial stored exactly once");

    // A trial the registry refuses for good is set aside, not retried forever nor lost.
    let mut foreign = trial("el-e-2");
    foreign.epc = Epc::parse(ADA_SWITCH).unwrap();
    let report = restarted.record_trial(&foreign).await.unwrap();
    assert_eq!(report.rejected, 1);
    let rejected = restarted.outbox().rejected().unwrap();
    assert!(rejected[0].1.contains("403"), "{:?}", rejected[0].1);
}

#[tokio::test]
async fn the_registry_is_reached_over_https_with_the_lans_own_certificate_authority() {
    let dir = tempfile::tempdir().unwrap();
    let made = rcgen::generate_simple_self_signed(vec!["localhost".to_owned()]).unwrap();
    let (cert, key) = (dir.path().join("pps.crt"), dir.path().join("pps.key"));
    std::fs::write(&cert, made.cert.pem()).unwrap();
    std::fs::write(&key, made.signing_key.serialize_pem()).unwrap();
    let transport = pps_server::transport::Transport {
        tls: Some(pps_server::transport::TlsIdentity::load(&cert, &key).unwrap()),
        ..Default::default()
    };
    let registry = RobotRegistry::start_with(Config { transport, ..Config::default() }).await;
    let (url, token) =
        (format!("https://localhost:{}", registry.address.port()), &registry.robot_token);

    let robot = RobotId::parse("el-e-1").unwrap();
    let epc = Epc::parse(ADA_SWITCH).unwrap();
    let untrusting =
        RegistryClient::new(&url, token, robot.clone(), &dir.path().join("a")).unwrap();
    assert!(untrusting.effective_entry(&epc).await.is_err(), "an unknown certificate is refused");
    let trusting = RegistryClient::new(&url, token, robot, &dir.path().join("b"))
        .unwrap()
        .with_ca_certificate(made.cert.pem().as_bytes())
        .unwrap();
    assert_eq!(trusting.effective_entry(&epc).await.unwrap().source, Source::Registry);
    assert_eq!(trusting.record_trial(&trial("el-e-1")).await.unwrap().uploaded, 1);
}

#[tokio::test(flavor = "multi_thread")]
async fn starting_up_reads_every_tag_and_forgets_the_archived_ones() {
    let dir = tempfile::tempdir().unwrap();
    let registry = RobotRegistry::start().await;
    let client = registry.client(dir.path());
    assert_eq!(client.sync_entries().await.unwrap(), 5);
    assert_eq!(client.known_entries().len(), 5);
    registry.archive_tag(DeviceKind::Lamp.epc().as_hex()).await;
    assert_eq!(client.sync_entries().await.unwrap(), 4);
    let known = client.known_entries();
    assert_eq!(known.len(), 4);
    assert!(known.iter().all(|e| e.epc != DeviceKind::Lamp.epc()));
}
