//! The client against answers the real registry should never give: a trial it keeps failing
//! on, a change feed that refuses the credential.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use pps_schema::{RobotId, Trial};
use pps_test_kit::wait_for;

use super::RegistryClient;
use super::client::MAX_FAILED_UPLOADS;
use super::flaky_registry::{self, Answer};

fn trial(n: u8) -> Trial {
    serde_json::from_value(serde_json::json!({
        "id": format!("00000000-0000-4000-8000-0000000000{n:02}"),
        "epc": "355AB1C60000002000000001", "robot": "el-e-1", "action": "on",
        "behavior": "push_top", "started_at": "2026-11-22T10:00:00Z",
        "finished_at": "2026-11-22T10:00:30Z", "outcome": "success"
    }))
    .unwrap()
}

#[tokio::test]
async fn a_trial_the_registry_keeps_failing_on_does_not_hold_up_the_rest() {
    let stored = Arc::new(AtomicUsize::new(0));
    let counted = stored.clone();
    let answer: Answer = Arc::new(move |_, path| {
        if path.ends_with("00000000-0000-4000-8000-000000000001") {
            (500, r#"{"status":500,"title":"Internal Server Error","detail":"a bug"}"#.into())
        } else {
            counted.fetch_add(1, Ordering::SeqCst);
            (201, "{}".into())
        }
    });
    let url = flaky_registry::serve(answer).await;
    let dir = tempfile::tempdir().unwrap();
    let client =
        RegistryClient::new(&url, "pps_x", RobotId::parse("el-e-1").unwrap(), dir.path()).unwrap();
    // The failing trial is the oldest: it heads the outbox.
    let mut report = client.record_trial(&trial(1)).await.unwrap();
    for n in 2..=4 {
        report = client.record_trial(&trial(n)).await.unwrap();
    }
    assert_eq!(stored.load(Ordering::SeqCst), 3, "the trials behind it were uploaded");
    assert_eq!(report.remaining, 1, "{report:?}");
    // Each of the four recordings tried it once; the flushes that follow try it again.
    for _ in 4..MAX_FAILED_UPLOADS {
        report = client.flush().await.unwrap();
    }
    assert_eq!((report.remaining, report.rejected), (0, 1), "set aside after {MAX_FAILED_UPLOADS}");
    let rejected = client.outbox().rejected().unwrap();
    assert!(rejected[0].1.contains("failed on this trial"), "{rejected:?}");
}

#[tokio::test]
async fn a_change_feed_that_refuses_the_credential_is_not_asked_again() {
    let asked = Arc::new(AtomicUsize::new(0));
    let counted = asked.clone();
    let answer: Answer = Arc::new(move |_, _| {
        counted.fetch_add(1, Ordering::SeqCst);
        (401, r#"{"status":401,"title":"Unauthorized","detail":"this token is not valid"}"#.into())
    });
    let url = flaky_registry::serve(answer).await;
    let dir = tempfile::tempdir().unwrap();
    let client =
        RegistryClient::new(&url, "pps_x", RobotId::parse("el-e-1").unwrap(), dir.path()).unwrap();
    let watch = client.watch_changes();
    let reason = "the watch to say it was refused, and stop";
    wait_for(Duration::from_secs(10), reason, || async {
        watch.refused().is_some() && watch.stopped()
    })
    .await;
    assert!(watch.refused().unwrap().contains("not valid"), "{:?}", watch.refused());
    // The watch has stopped: it can never ask again.
    assert_eq!(asked.load(Ordering::SeqCst), 1);
}
