//! Floods from one host on the LAN, bounded in count and time: made-up HTTP methods, clients
//! that send headers and stall their bodies, many wrong passwords at once. Each keeps the
//! server's memory bounded (read from `/proc/PID/status`) and other clients served.

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use pps_test_kit::Registry;
use pps_test_kit::{fixtures, wait};
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpSocket, TcpStream};

fn address(registry: &Registry) -> SocketAddr {
    registry.url.strip_prefix("http://").unwrap().parse().unwrap()
}

/// A connection to the registry from `source` (any 127.x.y.z address is this machine).
async fn connect_from(registry: &Registry, source: [u8; 4]) -> TcpStream {
    let socket = TcpSocket::new_v4().unwrap();
    socket.bind(SocketAddr::from((source, 0))).unwrap();
    socket.connect(address(registry)).await.unwrap()
}

#[tokio::test]
async fn made_up_methods_do_not_grow_the_metrics() {
    let registry = Registry::start();
    let client = reqwest::Client::new();
    let warm = client
        .request(Method::from_bytes(b"WARM").unwrap(), format!("{}/api/v1/tags", registry.url));
    assert_eq!(warm.send().await.unwrap().status(), StatusCode::METHOD_NOT_ALLOWED);
    let before = registry.memory_kib("VmRSS");
    let flood = (0..16).map(|worker| {
        let (client, url) = (client.clone(), registry.url.clone());
        tokio::spawn(async move {
            for n in 0..1250 {
                let method = Method::from_bytes(format!("M{worker}X{n}").as_bytes()).unwrap();
                let response = client.request(method, format!("{url}/api/v1/tags")).send().await;
                assert_eq!(response.unwrap().status(), StatusCode::METHOD_NOT_ALLOWED);
            }
        })
    });
    for worker in flood.collect::<Vec<_>>() {
        worker.await.unwrap();
    }
    let after = registry.memory_kib("VmRSS");
    let metrics = reqwest::get(format!("{}/metrics", registry.url)).await.unwrap();
    let text = metrics.text().await.unwrap();
    eprintln!("20,000 made-up methods: RSS {before} -> {after} KiB, /metrics {} bytes", text.len());
    assert!(after.saturating_sub(before) < 20 * 1024, "RSS grew {before} -> {after} KiB");
    assert!(text.len() < 64 * 1024, "/metrics is {} bytes", text.len());
    assert!(text.contains("method=\"other\",status=\"405\"} 20001"), "{text}");
}

/// Whether the server has closed `stream` (an end of file or a reset), without waiting.
async fn closed(stream: &TcpStream) -> bool {
    let mut byte = [0; 1];
    let peek = tokio::time::timeout(Duration::ZERO, stream.peek(&mut byte));
    matches!(peek.await, Ok(Ok(0) | Err(_)))
}

#[tokio::test]
async fn clients_stalling_their_bodies_leave_the_others_served() {
    let deadline = Duration::from_secs(2);
    let registry = Registry::with_flags(&["--body-timeout", &deadline.as_secs().to_string()]);
    // 512 connections from one host, quiet at first (the header deadline is 30 s): the first
    // 256 fill half of the server's connections, and each one after is beyond the host's share.
    let mut connections = Vec::new();
    for _ in 0..512 {
        connections.push(connect_from(&registry, [127, 0, 0, 2]).await);
    }
    // Only once the server has taken all 512 does a body start its deadline, so one cut off
    // cannot free a place in the host's share for a connection not yet taken.
    let all = &connections;
    wait::until("the connections beyond the host's share to be closed", || async move {
        let mut shut = 0;
        for stream in all {
            shut += usize::from(closed(stream).await);
        }
        (shut >= 256).then_some(())
    })
    .await;
    let mut stalled = Vec::new();
    for stream in connections {
        if !closed(&stream).await {
            stalled.push(stream);
        }
    }
    assert_eq!(stalled.len(), 256, "the host's share of the connections is held open");

    // Each sends the headers of a login and one byte of its body, then stalls.
    let head = "POST /api/v1/session HTTP/1.1\r\nhost: registry\r\n\
                content-type: application/json\r\ncontent-length: 100\r\n\r\n{";
    let stalling = Instant::now();
    for stream in &mut stalled {
        stream.write_all(head.as_bytes()).await.unwrap();
    }
    let client = reqwest::Client::builder().timeout(Duration::from_secs(5)).build().unwrap();
    let health = client.get(format!("{}/healthz", registry.url)).send().await;
    let answered = stalling.elapsed();
    eprintln!(
        "with 256 stalled bodies, /healthz answered {answered:?} after the first: {health:?}"
    );
    assert_eq!(health.expect("/healthz answers").status(), StatusCode::OK);
    assert!(answered < deadline, "answered after the stalled bodies' deadline: {answered:?}");

    // The stalled bodies are cut off after the body deadline with a 408, and closed.
    let mut first_cut = None;
    for stream in &mut stalled {
        let mut answer = Vec::new();
        let read = tokio::time::timeout(deadline * 5, stream.read_to_end(&mut answer));
        read.await.expect("a stalled connection is closed after its deadline").unwrap();
        assert!(answer.starts_with(b"HTTP/1.1 408"), "{}", String::from_utf8_lossy(&answer));
        first_cut.get_or_insert(stalling.elapsed());
    }
    let first_cut = first_cut.unwrap();
    eprintln!("the first stalled body was cut off {first_cut:?} after it stalled");
    assert!(first_cut >= deadline, "cut off after the deadline, not before: {first_cut:?}");
}

/// Logs in `n` times at once with wrong passwords, each from `source(i)`; the statuses.
async fn wrong_passwords_at_once(
    registry: &Registry,
    n: usize,
    name: impl Fn(usize) -> String,
    source: impl Fn(usize) -> [u8; 4],
) -> Vec<StatusCode> {
    let attempts = (0..n).map(|i| {
        let client = reqwest::Client::builder()
            .local_address(std::net::IpAddr::from(source(i)))
            .build()
            .unwrap();
        let url = format!("{}/api/v1/session", registry.url);
        let body = json!({ "username": name(i), "password": format!("wrong password {i}") });
        tokio::spawn(async move { client.post(url).json(&body).send().await.unwrap().status() })
    });
    let mut statuses = Vec::new();
    for attempt in attempts.collect::<Vec<_>>() {
        statuses.push(attempt.await.unwrap());
    }
    statuses
}

fn count(statuses: &[StatusCode], status: StatusCode) -> usize {
    statuses.iter().filter(|s| **s == status).count()
}

#[tokio::test]
async fn many_wrong_passwords_at_once_are_slowed_and_bounded() {
    let registry = Registry::start();
    registry.add_user("anna", "caretaker", "the right password");
    let baseline = registry.memory_kib("VmHWM");

    // One name, one host, 100 guesses at once: the throttle counts them as if one by one.
    let statuses =
        wrong_passwords_at_once(&registry, 100, |_| "anna".into(), |_| [127, 0, 0, 3]).await;
    let (checked, slowed) = (
        count(&statuses, StatusCode::UNAUTHORIZED),
        count(&statuses, StatusCode::TOO_MANY_REQUESTS),
    );
    eprintln!(
        "100 guesses for one name at once: {checked} checked (401), {slowed} slowed (429); \
         peak RSS {baseline} -> {} KiB",
        registry.memory_kib("VmHWM")
    );
    assert_eq!(checked + slowed, 100, "{statuses:?}");
    assert!(checked <= 4, "at most the free failures and one more are checked: {checked}");

    // 100 names from 100 hosts at once: each may be checked, but only a few hashes run at
    // once and the rest are told to retry.
    let statuses = wrong_passwords_at_once(
        &registry,
        100,
        |i| format!("name{i}"),
        |i| [127, 0, 1, i as u8 + 1],
    )
    .await;
    let (checked, busy) = (
        count(&statuses, StatusCode::UNAUTHORIZED),
        count(&statuses, StatusCode::SERVICE_UNAVAILABLE),
    );
    let peak = registry.memory_kib("VmHWM");
    eprintln!(
        "100 names at once: {checked} checked (401), {busy} told to retry (503); \
         peak RSS {baseline} -> {peak} KiB"
    );
    assert_eq!(checked + busy, 100, "{statuses:?}");
    assert!(peak.saturating_sub(baseline) < 600 * 1024, "peak RSS {baseline} -> {peak} KiB");
}

#[tokio::test]
async fn logins_from_many_hosts_hash_in_the_same_memory() {
    let registry = Registry::start();
    for n in 0..10 {
        registry.add_user(&format!("user{n}"), "caretaker", "the right password");
    }
    let baseline = registry.memory_kib("VmRSS");
    // 200 logins from 100 hosts, right and wrong by turns, eight at a time: each one hashes.
    let mut statuses = Vec::new();
    for wave in 0..25 {
        let logins = (0..8).map(|n| {
            let i = wave * 8 + n;
            let client = reqwest::Client::builder()
                .local_address(std::net::IpAddr::from([127, 0, 2, (i % 100) as u8 + 1]))
                .build()
                .unwrap();
            let url = format!("{}/api/v1/session", registry.url);
            let body = if i % 2 == 0 {
                json!({ "username": format!("user{}", i % 10), "password": "the right password" })
            } else {
                json!({ "username": format!("stranger{i}"), "password": format!("wrong {i}") })
            };
            tokio::spawn(async move { client.post(url).json(&body).send().await.unwrap().status() })
        });
        for login in logins.collect::<Vec<_>>() {
            statuses.push(login.await.unwrap());
        }
    }
    let peak = registry.memory_kib("VmHWM");
    eprintln!("200 logins from 100 hosts: peak RSS {baseline} -> {peak} KiB");
    assert_eq!(count(&statuses, StatusCode::OK), 100, "{statuses:?}");
    assert_eq!(count(&statuses, StatusCode::UNAUTHORIZED), 100, "{statuses:?}");
    // Four hashing threads' 19 MiB and room for the rest; a block per login would be gigabytes.
    assert!(peak.saturating_sub(baseline) < 120 * 1024, "peak RSS {baseline} -> {peak} KiB");
}

/// A connection from `source` that asks for the OpenAPI document `times` times in one go and
/// never reads an answer, its receive buffer made small so the server's writes stall at once.
async fn pipelining_non_reader(registry: &Registry, source: [u8; 4], times: usize) -> TcpStream {
    let socket = TcpSocket::new_v4().unwrap();
    socket.set_recv_buffer_size(4096).unwrap();
    socket.bind(SocketAddr::from((source, 0))).unwrap();
    let mut stream = socket.connect(address(registry)).await.unwrap();
    let request = "GET /api/v1/openapi.json HTTP/1.1\r\nhost: registry\r\n\r\n".repeat(times);
    // The server closes connections beyond the host's share; writing to one may fail.
    let _ = stream.write_all(request.as_bytes()).await;
    stream
}

#[tokio::test]
async fn two_hosts_that_never_read_leave_room_for_a_third() {
    let registry = Registry::with_flags(&["--max-connections", "64"]);
    let mut hogs = Vec::new();
    for source in [[127, 0, 0, 8], [127, 0, 0, 9]] {
        for _ in 0..32 {
            hogs.push(pipelining_non_reader(&registry, source, 60).await);
        }
    }
    let client = reqwest::Client::builder()
        .local_address(std::net::IpAddr::from([127, 0, 0, 10]))
        .timeout(Duration::from_secs(3))
        .build()
        .unwrap();
    let asked = Instant::now();
    let health = client.get(format!("{}/healthz", registry.url)).send().await;
    eprintln!("with 64 connections that never read, /healthz answered in {:?}", asked.elapsed());
    assert_eq!(health.expect("a third host is served within 3 s").status(), StatusCode::OK);
}

#[tokio::test]
async fn a_connection_that_never_reads_its_answers_is_closed_after_the_write_timeout() {
    let timeout = Duration::from_secs(1);
    let registry = Registry::with_flags(&[
        "--max-connections",
        "2",
        "--write-timeout",
        &timeout.as_secs().to_string(),
    ]);
    // Both connections go to one host that never reads what it asked for.
    let hogs = [
        pipelining_non_reader(&registry, [127, 0, 0, 8], 60).await,
        pipelining_non_reader(&registry, [127, 0, 0, 8], 60).await,
    ];
    let client = reqwest::Client::builder().timeout(timeout * 5).build().unwrap();
    let asked = Instant::now();
    let health = client.get(format!("{}/healthz", registry.url)).send().await;
    let waited = asked.elapsed();
    eprintln!("/healthz waited {waited:?} for a connection that never read to be closed");
    assert_eq!(health.expect("a slot was freed").status(), StatusCode::OK);
    assert!(waited >= timeout - Duration::from_millis(300), "{waited:?}");
    drop(hogs);
}

/// A gauge's value in the registry's Prometheus metrics.
async fn gauge(registry: &Registry, name: &str) -> usize {
    let text =
        reqwest::get(format!("{}/metrics", registry.url)).await.unwrap().text().await.unwrap();
    let line = text.lines().find(|line| line.split_whitespace().next() == Some(name));
    line.and_then(|line| line.split_whitespace().nth(1))
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("the metrics have no {name}"))
}

/// A connection from `source` that asks for a page of trials with their force samples
/// `times` times in one go and never reads, its receive buffer small so writes stall at once.
async fn heavy_non_reader(registry: &Registry, source: [u8; 4], token: &str) -> TcpStream {
    let socket = TcpSocket::new_v4().unwrap();
    socket.set_recv_buffer_size(4096).unwrap();
    socket.bind(SocketAddr::from((source, 0))).unwrap();
    let mut stream = socket.connect(address(registry)).await.unwrap();
    let request = format!(
        "GET /api/v1/trials?limit=500&include=forces HTTP/1.1\r\nhost: registry\r\n\
         authorization: Bearer {token}\r\n\r\n"
    );
    stream.write_all(request.repeat(20).as_bytes()).await.unwrap();
    stream
}

#[tokio::test]
async fn hosts_asking_for_heavy_pages_wait_their_turn_and_a_third_host_is_served_meanwhile() {
    let registry = Registry::start();
    let robot = fixtures::robot(&registry, "el-e-1", "el-e").await;
    // Twelve trials of 5,000 force samples: a page with forces is 4 MiB, cut short.
    for n in 0..12 {
        let mut trial = fixtures::switch_trial("el-e-1");
        let forces: Vec<Value> = (0..5000)
            .map(|i| {
                let x = f64::from(n * 5000 + i);
                json!({ "t": x * 0.001, "finger": "left", "force": [x.sin(), x.cos(), 2.0 + x.sin()] })
            })
            .collect();
        trial["forces"] = Value::from(forces);
        let (status, body) = fixtures::put_trial(&registry, &robot, &trial).await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
    }
    let mut hogs = Vec::new();
    for source in [[127, 0, 0, 8], [127, 0, 0, 9]] {
        for _ in 0..32 {
            hogs.push(heavy_non_reader(&registry, source, &robot).await);
        }
    }
    // Each host's requests queue behind its one turn; at most one core's worth is built at once.
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let queued = wait::until("both hosts' pages to queue up", || async {
        let waiting = gauge(&registry, "pps_heavy_answers_waiting").await;
        (waiting >= 32).then_some(waiting)
    })
    .await;
    let building = gauge(&registry, "pps_heavy_answers_building").await;
    assert!(
        building <= (cores - 1).max(1),
        "{building} heavy answers built at once on {cores} cores"
    );

    let third = reqwest::Client::builder()
        .local_address(std::net::IpAddr::from([127, 0, 0, 10]))
        .build()
        .unwrap();
    let health = third.get(format!("{}/healthz", registry.url)).send().await.unwrap();
    assert_eq!(health.status(), StatusCode::OK);
    let tags =
        third.get(format!("{}/api/v1/tags", registry.url)).bearer_auth(&registry.admin_token);
    assert_eq!(tags.send().await.unwrap().status(), StatusCode::OK);
    // A heavy page of its own waits for one turn, not behind the two hosts' backlogs.
    let page = third
        .get(format!("{}/api/v1/trials?limit=500&include=forces", registry.url))
        .bearer_auth(&robot)
        .send()
        .await
        .unwrap();
    assert_eq!(page.status(), StatusCode::OK);
    let page: Value = page.json().await.unwrap();
    assert!(page["next_cursor"].is_string(), "the page is cut short at 4 MiB");
    let still_waiting = gauge(&registry, "pps_heavy_answers_waiting").await;
    eprintln!(
        "{queued} heavy requests queued; {still_waiting} still queued after the third host's"
    );
    assert!(still_waiting > 0, "the third host was served before the two hosts' backlog");
    drop(hogs);
}
