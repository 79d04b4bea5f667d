//! Credentials: missing or bad ones are 401, roles without the right 403, and tokens minted or
//! revoked by another process take effect on a running server.

use std::time::Duration;

use pps_server::identity::Role;
use pps_server::store::tokens;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};

#[tokio::test]
async fn api_needs_a_credential_but_open_routes_do_not() {
    let server = TestServer::start().await;
    for path in ["/api/v1/tags", "/api/v1/tags/355AB1C60000002000000001"] {
        let response = server.request(Method::GET, path, None).send().await.unwrap();
        assert_eq!(response.headers()["www-authenticate"], "Bearer");
        problem(response, StatusCode::UNAUTHORIZED).await;
    }
    for bad in ["Bearer pps_nope", "Basic YWRtaW46YWRtaW4=", "Bearer "] {
        let response = server
            .request(Method::GET, "/api/v1/tags", None)
            .header("authorization", bad)
            .send()
            .await
            .unwrap();
        problem(response, StatusCode::UNAUTHORIZED).await;
    }
    let forged = format!("pps_{}", "A".repeat(43));
    problem(server.get("/api/v1/tags", &forged).await, StatusCode::UNAUTHORIZED).await;
    for open in ["/healthz", "/api/v1/schema/tag", "/"] {
        assert_eq!(
            server.request(Method::GET, open, None).send().await.unwrap().status(),
            StatusCode::OK,
            "{open}"
        );
    }
}

#[tokio::test]
async fn robots_read_tags_but_cannot_edit_them() {
    let server = TestServer::start().await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let caretaker = server.token(Role::Caretaker, "nurse").await;
    assert_eq!(server.get("/api/v1/tags", &robot).await.status(), StatusCode::OK);
    let entry = new_entry("E20034120000000000004242", "new");
    let path = "/api/v1/tags/E20034120000000000004242";
    problem(
        server.put(path, &robot, &entry, Some(("if-none-match", "*"))).await,
        StatusCode::FORBIDDEN,
    )
    .await;
    problem(
        server.get(&format!("/api/v1/tags/{ADA_SWITCH}/revisions"), &robot).await,
        StatusCode::FORBIDDEN,
    )
    .await;
    let created = server.put(path, &caretaker, &entry, Some(("if-none-match", "*"))).await;
    assert_eq!(created.status(), StatusCode::CREATED);
    let created: serde_json::Value = created.json().await.unwrap();
    assert_eq!(created["updated_by"], "nurse");
}

#[tokio::test]
async fn tokens_from_another_process_work_at_once_and_revocation_bites_within_seconds() {
    let server = TestServer::start().await;
    // A second handle on the file stands in for the CLI process.
    let cli = pps_server::Db::open(&server.location).await.unwrap();
    let minted = tokens::create(&cli, Role::Caretaker, "late nurse", None).await.unwrap();
    assert_eq!(server.get("/api/v1/tags", &minted.token).await.status(), StatusCode::OK);
    assert!(tokens::revoke(&cli, &minted.record.id).await.unwrap());
    // A token confirmed recently is trusted from memory; past that, the revocation bites.
    server.advance(pps_server::auth::TOKEN_RECHECK_AFTER);
    problem(server.get("/api/v1/tags", &minted.token).await, StatusCode::UNAUTHORIZED).await;

    let soon = server.now() + Duration::from_secs(60);
    let expiring = tokens::create(&cli, Role::Admin, "short", Some(soon)).await.unwrap();
    assert_eq!(server.get("/api/v1/tags", &expiring.token).await.status(), StatusCode::OK);
    server.advance(Duration::from_secs(60));
    problem(server.get("/api/v1/tags", &expiring.token).await, StatusCode::UNAUTHORIZED).await;

    let expired =
        tokens::create(&cli, Role::Admin, "expired", Some(server.now() - Duration::from_secs(1)))
            .await
            .unwrap();
    problem(server.get("/api/v1/tags", &expired.token).await, StatusCode::UNAUTHORIZED).await;
}

#[tokio::test]
async fn only_hashes_of_tokens_are_stored() {
    let server = TestServer::start_sqlite().await;
    let token = server.token(Role::Caretaker, "nurse").await;
    server.db.close().await;
    let bytes = std::fs::read(&server.db_path).unwrap();
    let wal = std::fs::read(server.db_path.with_extension("db-wal")).unwrap_or_default();
    for file in [bytes, wal] {
        assert!(
            !file.windows(token.len()).any(|w| w == token.as_bytes()),
            "a token is stored in plain text"
        );
    }
}

#[tokio::test]
async fn admins_manage_tokens_over_the_api_and_revocation_is_immediate() {
    let server = TestServer::start().await;
    let created = server
        .request(Method::POST, "/api/v1/tokens", Some(&server.admin))
        .json(&serde_json::json!({ "role": "robot", "name": "el-e-1", "expires_in_days": 30 }))
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    let created: serde_json::Value = created.json().await.unwrap();
    let token = created["token"].as_str().unwrap().to_owned();
    assert_eq!(created["robot_id"], "el-e-1");
    assert!(created["expires_at"].is_string());
    assert_eq!(server.get("/api/v1/tags", &token).await.status(), StatusCode::OK);

    let listed: serde_json::Value =
        server.get("/api/v1/tokens", &server.admin).await.json().await.unwrap();
    assert!(!listed.to_string().contains(&token), "secrets are shown once");
    problem(server.get("/api/v1/tokens", &token).await, StatusCode::FORBIDDEN).await;
    let bad = server
        .request(Method::POST, "/api/v1/tokens", Some(&server.admin))
        .json(&serde_json::json!({ "role": "robot", "name": "Not Valid" }))
        .send()
        .await
        .unwrap();
    problem(bad, StatusCode::UNPROCESSABLE_ENTITY).await;

    let id = created["id"].as_str().unwrap();
    let revoked = server
        .request(Method::DELETE, &format!("/api/v1/tokens/{id}"), Some(&server.admin))
        .send()
        .await
        .unwrap();
    assert_eq!(revoked.status(), StatusCode::OK);
    problem(server.get("/api/v1/tags", &token).await, StatusCode::UNAUTHORIZED).await;
    let again = server
        .request(Method::DELETE, &format!("/api/v1/tokens/{id}"), Some(&server.admin))
        .send()
        .await
        .unwrap();
    problem(again, StatusCode::NOT_FOUND).await;
}
