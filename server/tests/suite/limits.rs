//! Every limit of the API at N−1, N and N+1, through HTTP: request body size, page size, force
//! samples per trial, EPC length, robot id length, and change-feed clients. The answer at N+1
//! is problem+json naming the limit; at N and N−1 the request goes through.

use std::time::Duration;

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

/// A JSON object of exactly `len` bytes.
fn body_of(len: usize) -> String {
    const FRAME: usize = "{\"pad\": \"\"}".len();
    let body = format!("{{\"pad\": \"{}\"}}", "x".repeat(len - FRAME));
    assert_eq!(body.len(), len);
    body
}

#[tokio::test]
async fn bodies_up_to_one_mebibyte_are_read() {
    let server = TestServer::start().await;
    let limit = pps_server::http::extract::MAX_BODY_BYTES;
    assert_eq!(limit, 1_048_576);
    for (len, status) in [
        (limit - 1, StatusCode::UNPROCESSABLE_ENTITY),
        (limit, StatusCode::UNPROCESSABLE_ENTITY),
        (limit + 1, StatusCode::PAYLOAD_TOO_LARGE),
    ] {
        let response = server
            .request(Method::POST, "/api/v1/validate/tag", Some(&server.admin))
            .header("content-type", "application/json")
            .body(body_of(len))
            .send()
            .await
            .unwrap();
        // 422: read, parsed and found not to be an entry; 413: never read.
        let body = problem(response, status).await;
        if status == StatusCode::PAYLOAD_TOO_LARGE {
            assert!(body["detail"].as_str().unwrap().contains("1048576 bytes"), "{body}");
        }
    }
}

#[tokio::test]
async fn every_list_pages_up_to_five_hundred() {
    let server = TestServer::start().await;
    let lists: Vec<_> = server
        .route_table()
        .into_iter()
        .filter(|route| route.doc.params.iter().any(|param| param.name == "limit"))
        .collect();
    assert!(lists.len() >= 6, "tags, revisions, robots, inbox, trials, users");
    let max = pps_server::http::page::MAX_LIMIT;
    assert_eq!(max, 500);
    for route in lists {
        let path = route.path.replace("{epc}", ADA_SWITCH);
        for (limit, status) in
            [(max - 1, StatusCode::OK), (max, StatusCode::OK), (max + 1, StatusCode::BAD_REQUEST)]
        {
            let response = server.get(&format!("{path}?limit={limit}"), &server.admin).await;
            if status == StatusCode::OK {
                assert_eq!(response.status(), status, "{path}?limit={limit}");
                let page: Value = response.json().await.unwrap();
                assert!(page["items"].is_array(), "{path}: {page}");
            } else {
                let body = problem(response, status).await;
                assert!(body["detail"].as_str().unwrap().contains("at most 500"), "{path}: {body}");
            }
        }
    }
}

#[tokio::test]
async fn a_trial_carries_up_to_the_force_sample_cap() {
    let server = TestServer::start().await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let cap = pps_schema::MAX_FORCE_SAMPLES;
    let sample = json!({ "t": 0.1, "finger": "left", "force": [1.0, 2.0, 3.0] });
    for (samples, status) in [
        (cap - 1, StatusCode::CREATED),
        (cap, StatusCode::CREATED),
        (cap + 1, StatusCode::PAYLOAD_TOO_LARGE),
    ] {
        let id = uuid::Uuid::new_v4().to_string();
        let mut body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
        body["forces"] = Value::Array(vec![sample.clone(); samples]);
        let response = server.put(&format!("/api/v1/trials/{id}"), &robot, &body, None).await;
        if status == StatusCode::CREATED {
            assert_eq!(response.status(), status, "{samples} samples");
            let stored: Value = response.json().await.unwrap();
            assert_eq!(stored["forces"].as_array().unwrap().len(), samples);
        } else {
            let body = problem(response, status).await;
            assert!(body["detail"].as_str().unwrap().contains(&cap.to_string()), "{body}");
        }
    }
}

#[tokio::test]
async fn epcs_are_four_to_one_hundred_twenty_four_hex_digits_in_whole_words() {
    let server = TestServer::start().await;
    for (digits, status) in [
        (3, StatusCode::BAD_REQUEST),
        (4, StatusCode::CREATED),
        (5, StatusCode::BAD_REQUEST),
        (120, StatusCode::CREATED),
        (124, StatusCode::CREATED),
        (128, StatusCode::BAD_REQUEST),
    ] {
        let epc = "A".repeat(digits);
        let path = format!("/api/v1/tags/{epc}");
        let entry = new_entry(&epc, &format!("{digits} digits"));
        let response = server.put(&path, &server.admin, &entry, Some(("if-none-match", "*"))).await;
        if status == StatusCode::CREATED {
            assert_eq!(response.status(), status, "{digits} digits");
            assert_eq!(server.get_json(&path).await["epc"], epc.as_str());
        } else {
            let body = problem(response, status).await;
            assert!(body["detail"].as_str().unwrap().contains("4 to 124"), "{body}");
        }
    }
}

#[tokio::test]
async fn robot_ids_are_at_most_sixty_three_characters() {
    let server = TestServer::start().await;
    for (len, status) in
        [(62, StatusCode::CREATED), (63, StatusCode::CREATED), (64, StatusCode::BAD_REQUEST)]
    {
        let id = format!("el-e-{}", "1".repeat(len - 5));
        let robot = json!({ "name": "long", "capabilities": ["push"] });
        let response =
            server.put(&format!("/api/v1/robots/{id}"), &server.admin, &robot, None).await;
        if status == StatusCode::CREATED {
            assert_eq!(response.status(), status, "{len} characters");
        } else {
            let body = problem(response, status).await;
            assert!(body["detail"].as_str().unwrap().contains("at most 63"), "{body}");
        }
    }
}

/// Holds one place of the change feed: a raw connection that read the answer's head and
/// nothing more, far cheaper than an HTTP client per place. It comes from 127.0.0.`host`, so
/// the places do not count against the test client's own address, and a screen's places
/// from its own host, as the server holds each host to its share once it is busy.
async fn hold_feed_place(server: &TestServer, token: &str, host: u8) -> TcpStream {
    hold_feed_place_as(server, &format!("authorization: Bearer {token}"), host).await
}

/// [`hold_feed_place`] with `credential` as the request's credential header line.
async fn hold_feed_place_as(server: &TestServer, credential: &str, host: u8) -> TcpStream {
    let address = server.url.strip_prefix("http://").unwrap();
    let socket = tokio::net::TcpSocket::new_v4().unwrap();
    socket.bind(std::net::SocketAddr::from(([127, 0, 0, host], 0))).unwrap();
    let mut stream = socket.connect(address.parse().unwrap()).await.unwrap();
    let request = format!("GET /api/v1/events HTTP/1.1\r\nhost: {address}\r\n{credential}\r\n\r\n");
    stream.write_all(request.as_bytes()).await.unwrap();
    let mut head = Vec::new();
    let mut chunk = [0u8; 512];
    while !head.windows(4).any(|w| w == b"\r\n\r\n") {
        let read = stream.read(&mut chunk).await.unwrap();
        assert!(read > 0, "the feed hung up before answering");
        head.extend_from_slice(&chunk[..read]);
    }
    let head = String::from_utf8_lossy(&head);
    assert!(head.starts_with("HTTP/1.1 200"), "{head}");
    stream
}

async fn feed_clients(server: &TestServer) -> usize {
    let metrics = server.request(Method::GET, "/metrics", None).send().await.unwrap();
    let text = metrics.text().await.unwrap();
    let line = text.lines().find(|l| l.starts_with("pps_sse_clients ")).expect("the gauge");
    line["pps_sse_clients ".len()..].parse().unwrap()
}

#[tokio::test]
async fn the_change_feed_serves_two_hundred_fifty_six_clients_at_once() {
    let server = TestServer::start().await;
    let cap = pps_server::feed::MAX_CLIENTS;
    let share = pps_server::feed::MAX_CLIENTS_PER_CREDENTIAL;
    assert_eq!((cap, share), (256, 64));
    let mut tokens = Vec::new();
    for n in 0..cap / share {
        tokens.push(server.token(Role::Caretaker, &format!("screen {n}")).await);
    }
    let mut held = Vec::with_capacity(cap);
    for n in 0..cap - 1 {
        held.push(hold_feed_place(&server, &tokens[n / share], 2 + (n / share) as u8).await);
    }
    // One credential's share: its next stream is refused although the feed has room.
    let over_share = server.request(Method::GET, "/api/v1/events", Some(&tokens[0])).send().await;
    let body = problem(over_share.unwrap(), StatusCode::SERVICE_UNAVAILABLE).await;
    assert!(body["detail"].as_str().unwrap().contains("64 change-feed streams"), "{body}");
    // N: the last place is free.
    let last = SseClient::connect(&server, tokens.last().unwrap(), None).await;
    assert_eq!(feed_clients(&server).await, cap);
    // N+1: refused while all are taken, whoever asks.
    let refused =
        server.request(Method::GET, "/api/v1/events", Some(&server.admin)).send().await.unwrap();
    assert!(refused.headers().contains_key("retry-after"));
    let body = problem(refused, StatusCode::SERVICE_UNAVAILABLE).await;
    assert!(body["detail"].as_str().unwrap().contains("256 clients"), "{body}");

    // A client leaving frees its place for the next one.
    drop(last);
    wait_for(Duration::from_secs(30), "the place to be freed", || async {
        feed_clients(&server).await < cap
    })
    .await;
    held.push(hold_feed_place(&server, &server.admin, 10).await);
    assert_eq!(feed_clients(&server).await, cap);
}

#[tokio::test]
async fn one_caretaker_logged_in_five_times_holds_one_share_of_the_feed() {
    use pps_server::auth::session;
    use pps_server::identity::secret;
    let server = TestServer::start().await;
    let anna = pps_server::identity::UserName::parse("anna").unwrap();
    pps_server::store::users::create(&server.db, &anna, Role::Caretaker, "unused").await.unwrap();
    let now = server.now();
    let mut cookies = Vec::new();
    for _ in 0..5 {
        let login = session::mint_secret();
        let hash = secret::hash(&login);
        pps_server::store::sessions::create(&server.db, &hash, &anna, now, now + session::LIFETIME)
            .await
            .unwrap();
        cookies.push(format!("cookie: {}={login}", session::COOKIE_NAME));
    }
    let share = pps_server::feed::MAX_CLIENTS_PER_CREDENTIAL;
    let mut held = Vec::with_capacity(share);
    for n in 0..share {
        held.push(hold_feed_place_as(&server, &cookies[n % 4], 2).await);
    }
    let fifth_login = server
        .request(Method::GET, "/api/v1/events", None)
        .header("cookie", cookies[4].trim_start_matches("cookie: "))
        .send()
        .await
        .unwrap();
    let body = problem(fifth_login, StatusCode::SERVICE_UNAVAILABLE).await;
    let detail = body["detail"].as_str().unwrap();
    assert!(detail.starts_with("user anna already holds 64 change-feed streams"), "{detail}");
    assert_eq!(feed_clients(&server).await, share, "the refused stream holds no place");
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let _robot_feed = SseClient::connect(&server, &robot, None).await;
    assert_eq!(feed_clients(&server).await, share + 1, "a robot still gets its stream");
}
