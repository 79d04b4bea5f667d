//! A full disk: the database on a 3 MB tmpfs, trials of ~100 KB until the disk is full. While
//! full, writes are answered 503 with `Retry-After` (never 500), `/readyz` says the registry
//! cannot write and the log says the disk is full; once the file system has room again, writes
//! succeed without a restart.
//!
//! Mounting needs root (as CI has); elsewhere the test says so and passes without running.

use std::path::Path;
use std::process::Command;

use pps_test_kit::Registry;
use pps_test_kit::fixtures::{self, put_trial};
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

/// A tmpfs mounted on a temporary directory, unmounted when dropped.
struct SmallDisk {
    dir: tempfile::TempDir,
}

impl SmallDisk {
    fn mount(size: &str) -> Result<Self, String> {
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        let output = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(dir.path())
            .output()
            .map_err(|e| format!("cannot run mount: {e}"))?;
        if !output.status.success() {
            return Err(String::from_utf8_lossy(&output.stderr).trim().to_owned());
        }
        Ok(Self { dir })
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    fn grow(&self, size: &str) {
        let status = Command::new("mount")
            .args(["-o", &format!("remount,size={size}")])
            .arg(self.path())
            .status()
            .unwrap();
        assert!(status.success(), "remounting the tmpfs larger");
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.path()).status();
    }
}

/// A trial of about 100 KB (its measurements carry a long note).
fn bulky_trial(robot: &str) -> Value {
    let mut trial = fixtures::switch_trial(robot);
    trial["measurements"] = json!({ "note": "x".repeat(100_000) });
    trial
}

async fn status_and_retry_after(
    response: reqwest::Response,
) -> (StatusCode, Option<String>, Value) {
    let status = response.status();
    let retry = response.headers().get("retry-after").map(|v| v.to_str().unwrap().to_owned());
    (status, retry, response.json().await.unwrap_or(Value::Null))
}

#[tokio::test]
async fn a_full_disk_answers_503_and_writes_resume_when_space_is_back() {
    let disk = match SmallDisk::mount("3m") {
        Ok(disk) => disk,
        Err(why) => {
            eprintln!(
                "SKIPPED: cannot mount a 3 MB tmpfs for the disk-full test ({why}); run as root"
            );
            return;
        }
    };
    let registry = Registry::on_database(&disk.path().join("pps.db"));
    let robot = fixtures::robot(&registry, "el-e-1", "el-e").await;

    let mut stored = 0;
    let refused = loop {
        let (status, body) = put_trial(&registry, &robot, &bulky_trial("el-e-1")).await;
        if status != StatusCode::CREATED {
            break (status, body);
        }
        stored += 1;
        assert!(stored < 100, "a 3 MB disk took {stored} trials of 100 KB");
    };
    eprintln!("disk full after {stored} trials: {} {}", refused.0, refused.1);
    assert_eq!(refused.0, StatusCode::SERVICE_UNAVAILABLE, "{}", refused.1);
    assert!(refused.1["detail"].as_str().unwrap().contains("disk is full"), "{}", refused.1);
    pps_test_kit::wait::until("the log to say the disk is full", || async {
        registry.logged("disk holding the database is full").then_some(())
    })
    .await;

    // While full, no write fails with a 500: bulky ones are refused with a 503 that says when
    // to retry. (A small write may still fit in pages the database already holds, so whether
    // one succeeds says nothing; only bulky writes are tried.)
    for _ in 0..3 {
        let trial = bulky_trial("el-e-1");
        let path = format!("/api/v1/trials/{}", trial["id"].as_str().unwrap());
        let request = registry.request(Method::PUT, &path, &robot).json(&trial);
        let (status, retry, body) = status_and_retry_after(request.send().await.unwrap()).await;
        assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE, "{body}");
        assert!(retry.is_some(), "a 503 says when to retry");
    }
    let ready = registry.request(Method::GET, "/readyz", "").send().await.unwrap();
    let (status, retry, body) = status_and_retry_after(ready).await;
    assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE, "{body}");
    assert!(retry.is_some());
    assert!(body["detail"].as_str().unwrap().contains("free"), "{body}");
    let live = registry.request(Method::GET, "/healthz", "").send().await.unwrap();
    assert_eq!(live.status(), StatusCode::OK);

    // Room again: the same server takes writes, tokens and trials alike.
    disk.grow("64m");
    let ready = registry.request(Method::GET, "/readyz", "").send().await.unwrap();
    assert_eq!(ready.status(), StatusCode::OK, "ready once there is room");
    let (status, body) = put_trial(&registry, &robot, &bulky_trial("el-e-1")).await;
    assert_eq!(status, StatusCode::CREATED, "{body}");
    let token = registry
        .request(Method::POST, "/api/v1/tokens", &registry.admin_token)
        .json(&json!({ "role": "caretaker", "name": "nurse" }));
    assert_eq!(token.send().await.unwrap().status(), StatusCode::CREATED);
    drop(registry);
}
