//! The task queue as its two sides call it over the API: a caretaker (the test's admin) asks
//! for a task, a robot claims one.

use reqwest::{Method, Response, StatusCode};
use serde_json::Value;

use crate::in_process::TestServer;

/// Asks for a task with `body`, as the test's admin; the answer as it came.
pub async fn ask(server: &TestServer, body: Value) -> Response {
    let request = server.request(Method::POST, "/api/v1/tasks", Some(&server.admin));
    request.json(&body).send().await.unwrap()
}

/// [`ask`], which must be accepted: the task as stored.
pub async fn asked(server: &TestServer, body: Value) -> Value {
    let response = ask(server, body).await;
    assert_eq!(response.status(), StatusCode::CREATED);
    response.json().await.unwrap()
}

/// Claims the next task for `robot`, waiting up to `wait` seconds for one.
pub async fn claim(server: &TestServer, token: &str, robot: &str, wait: f64) -> Response {
    let path = format!("/api/v1/robots/{robot}/tasks/claim?wait={wait}");
    server.request(Method::POST, &path, Some(token)).send().await.unwrap()
}
