//! Another process holding the database's write lock (a long `BEGIN IMMEDIATE`) makes writes
//! wait for the lock timeout, then answer 503 with `Retry-After`, never 500; reads go on, and
//! writes resume once the lock is let go.

use std::time::{Duration, Instant};

use pps_test_kit::Registry;
use reqwest::{Method, StatusCode};
use serde_json::json;
use sqlx::Connection;

#[tokio::test]
async fn a_database_locked_by_another_process_answers_503() {
    // The operator's knob, at its smallest: the test waits out the timeout in real time.
    let lock_timeout = Duration::from_secs(1);
    let registry = Registry::with_flags(&["--lock-timeout", "1"]);
    let options = sqlx::sqlite::SqliteConnectOptions::new().filename(registry.db_path());
    let mut holder = sqlx::SqliteConnection::connect_with(&options).await.unwrap();
    sqlx::raw_sql("begin immediate").execute(&mut holder).await.unwrap();

    let asked = Instant::now();
    let write = registry
        .request(Method::POST, "/api/v1/tokens", &registry.admin_token)
        .json(&json!({ "role": "caretaker", "name": "nurse" }))
        .send()
        .await
        .unwrap();
    let waited = asked.elapsed();
    let status = write.status();
    let retry_after = write.headers().get("retry-after").cloned();
    let content_type = write.headers().get("content-type").cloned();
    let body: serde_json::Value = write.json().await.unwrap();
    eprintln!("a write while another process held the lock: {status} after {waited:?}: {body}");
    assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE, "{body}");
    assert!(waited >= lock_timeout, "the write waited for the lock first ({waited:?})");
    assert_eq!(content_type.unwrap(), "application/problem+json");
    assert!(retry_after.is_some(), "a 503 says when to retry");
    assert!(body["detail"].as_str().unwrap().contains("locked"), "{body}");
    let read = registry.request(Method::GET, "/api/v1/tags", &registry.admin_token).send();
    assert_eq!(read.await.unwrap().status(), StatusCode::OK, "reads go on meanwhile");
    let ready = registry.request(Method::GET, "/readyz", "").send().await.unwrap();
    assert_eq!(ready.status(), StatusCode::SERVICE_UNAVAILABLE, "not ready while locked");
    let ready: serde_json::Value = ready.json().await.unwrap();
    let said = ready["detail"].as_str().unwrap();
    assert!(said.contains("stayed locked for 1 s"), "{ready}");

    sqlx::raw_sql("rollback").execute(&mut holder).await.unwrap();
    let write = registry
        .request(Method::POST, "/api/v1/tokens", &registry.admin_token)
        .json(&json!({ "role": "caretaker", "name": "nurse" }))
        .send()
        .await
        .unwrap();
    assert_eq!(write.status(), StatusCode::CREATED, "writes resume once the lock is let go");
}
