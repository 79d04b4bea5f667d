//! Every error is problem+json: unknown routes, wrong methods, oversized, mistyped and
//! malformed bodies, malformed EPCs.

use pps_test_kit::*;
use reqwest::{Method, StatusCode};

#[tokio::test]
async fn unknown_routes_and_methods() {
    let server = TestServer::start().await;
    problem(
        server.request(Method::GET, "/api/v1/nothing", Some(&server.admin)).send().await.unwrap(),
        StatusCode::NOT_FOUND,
    )
    .await;
    for method in [Method::TRACE, Method::PATCH, Method::POST] {
        let response = server
            .request(method.clone(), "/api/v1/tags", Some(&server.admin))
            .send()
            .await
            .unwrap();
        assert!(response.headers().contains_key("allow"), "{method}");
        problem(response, StatusCode::METHOD_NOT_ALLOWED).await;
    }
}

#[tokio::test]
async fn malformed_epc_in_the_path_is_named() {
    let server = TestServer::start().await;
    for (epc, needle) in [("12x4", "'x'"), ("ABC", "3"), ("ABCDE", "5")] {
        let body = problem(
            server.get(&format!("/api/v1/tags/{epc}"), &server.admin).await,
            StatusCode::BAD_REQUEST,
        )
        .await;
        assert!(body["detail"].as_str().unwrap().contains(needle), "{epc}: {body}");
    }
}

#[tokio::test]
async fn bodies_too_large_mistyped_or_malformed() {
    let server = TestServer::start().await;
    let path = "/api/v1/validate/tag";
    let limit = 1 << 20;
    let at_limit = format!("{{\"pad\": \"{}\"}}", "x".repeat(limit - 11));
    assert_eq!(at_limit.len(), limit);
    let send = |body: String, media: &'static str| {
        server
            .request(Method::POST, path, Some(&server.admin))
            .header("content-type", media)
            .body(body)
            .send()
    };
    let response = send(at_limit.clone(), "application/json").await.unwrap();
    assert_eq!(
        response.status(),
        StatusCode::UNPROCESSABLE_ENTITY,
        "1 MiB exactly is read and validated"
    );
    let over = format!("{at_limit} ");
    problem(send(over, "application/json").await.unwrap(), StatusCode::PAYLOAD_TOO_LARGE).await;
    problem(send("{}".into(), "text/plain").await.unwrap(), StatusCode::UNSUPPORTED_MEDIA_TYPE)
        .await;
    let body = problem(
        send("{\n  \"epc\": ,\n}".into(), "application/json").await.unwrap(),
        StatusCode::BAD_REQUEST,
    )
    .await;
    let detail = body["detail"].as_str().unwrap();
    assert!(detail.contains("line 2") && detail.contains("column"), "{detail}");
}
