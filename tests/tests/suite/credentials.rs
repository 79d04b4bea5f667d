//! A credential that stops being valid stops everything it opened: a change-feed stream ends
//! within seconds of its token's revocation (by the CLI or the API), its session's logout, or
//! its user's deletion.

use std::time::{Duration, Instant};

use pps_test_kit::Registry;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

/// Opens the change feed with `request` and returns the streaming response.
async fn open_feed(request: reqwest::RequestBuilder) -> reqwest::Response {
    let response = request.send().await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    response
}

/// How long the stream kept going after `since`; panics if it outlives 15 s.
async fn ends_within(mut stream: reqwest::Response, since: Instant) -> Duration {
    loop {
        match tokio::time::timeout(Duration::from_secs(15), stream.chunk()).await {
            Ok(Ok(Some(_))) => continue,
            Ok(_) => return since.elapsed(),
            Err(_) => panic!("the stream still ran 15 s after its credential ended"),
        }
    }
}

#[tokio::test]
async fn a_revoked_token_ends_its_open_feed() {
    let registry = Registry::start();
    let token = registry.token("caretaker", "tablet");
    let stream = open_feed(registry.request(Method::GET, "/api/v1/events", &token)).await;
    let id = token_id(&registry, "tablet").await;
    let output = registry.cli(&["token", "revoke", &id]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let after = ends_within(stream, Instant::now()).await;
    eprintln!("feed of a token revoked by the CLI ended after {after:?}");

    // Revoked through the API, too.
    let token = registry.token("caretaker", "phone");
    let stream = open_feed(registry.request(Method::GET, "/api/v1/events", &token)).await;
    let id = token_id(&registry, "phone").await;
    let path = format!("/api/v1/tokens/{id}");
    let (status, _) = registry.call(Method::DELETE, &path, &registry.admin_token, None, &[]).await;
    assert_eq!(status, StatusCode::OK);
    let after = ends_within(stream, Instant::now()).await;
    eprintln!("feed of a token revoked through the API ended after {after:?}");
}

#[tokio::test]
async fn logout_and_user_deletion_end_the_sessions_feeds() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", "the right password");
    let client = reqwest::Client::new();
    let login = |client: reqwest::Client| {
        let url = format!("{}/api/v1/session", registry.url);
        async move {
            let response = client
                .post(url)
                .json(&json!({ "username": "anna", "password": "the right password" }))
                .send()
                .await
                .unwrap();
            assert_eq!(response.status(), StatusCode::OK);
            let cookie = response.headers()["set-cookie"].to_str().unwrap();
            let cookie = cookie.split(';').next().unwrap().to_owned();
            let csrf =
                response.json::<Value>().await.unwrap()["csrf_token"].as_str().unwrap().to_owned();
            (cookie, csrf)
        }
    };
    let feed = |cookie: &str| {
        client.get(format!("{}/api/v1/events", registry.url)).header("cookie", cookie)
    };

    let (cookie, csrf) = login(client.clone()).await;
    let stream = open_feed(feed(&cookie)).await;
    let logout = client
        .delete(format!("{}/api/v1/session", registry.url))
        .header("cookie", &cookie)
        .header("x-csrf-token", csrf)
        .send()
        .await
        .unwrap();
    assert_eq!(logout.status(), StatusCode::NO_CONTENT);
    let after = ends_within(stream, Instant::now()).await;
    eprintln!("feed of a logged-out session ended after {after:?}");

    let (cookie, _) = login(client.clone()).await;
    let stream = open_feed(feed(&cookie)).await;
    let (status, body) =
        registry.call(Method::DELETE, "/api/v1/users/anna", &registry.admin_token, None, &[]).await;
    assert!(status.is_success(), "{status} {body}");
    let after = ends_within(stream, Instant::now()).await;
    eprintln!("feed of a deleted user's session ended after {after:?}");
}

async fn token_id(registry: &Registry, name: &str) -> String {
    let tokens = registry.get("/api/v1/tokens").await;
    let items = tokens["items"].as_array().unwrap();
    let token = items.iter().find(|t| t["name"] == name).expect("the token is listed");
    token["id"].as_str().unwrap().to_owned()
}
