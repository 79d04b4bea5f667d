//! How the server holds connections: slow clients are cut off, connections beyond the cap
//! wait, HTTPS with the operator's certificate, and a shutdown that ends streams and returns.

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use http_body_util::{BodyExt, Empty};
use hyper::body::Bytes;
use hyper_util::rt::TokioIo;
use pps_server::transport::{TlsIdentity, Transport};
use pps_test_kit::{Config, Registry, Store, TestServer};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio_rustls::rustls;

/// Short, so the tests are quick; the trickling client still needs several bytes to fail.
const HEADER_TIMEOUT: Duration = Duration::from_secs(1);
/// How often the trickling client sends a byte: several within the header timeout, each of
/// which would restart a timer that counted idle time instead of the whole request's.
const TRICKLE_EVERY: Duration = Duration::from_millis(250);

/// An in-process registry on a SQLite file, holding connections as `transport` says.
async fn serve(transport: Transport) -> TestServer {
    TestServer::start_with(Config { store: Store::Sqlite, transport, ..Config::default() }).await
}

fn transport(max_connections: usize) -> Transport {
    Transport {
        header_read_timeout: HEADER_TIMEOUT,
        max_connections,
        max_connections_per_address: max_connections,
        ..Transport::default()
    }
}

/// Connects and sends half a request line, as a slow (or hostile) client does.
async fn half_a_request(address: SocketAddr) -> TcpStream {
    let mut stream = TcpStream::connect(address).await.unwrap();
    stream.write_all(b"GET /healthz HT").await.unwrap();
    stream
}

/// Trickles the rest of a request one byte every [`TRICKLE_EVERY`] until the server hangs up;
/// returns how long after connecting that was.
async fn trickle_until_cut_off(mut stream: TcpStream, connected: Instant) -> Duration {
    let rest = b"TP/1.1\r\nHost: registry\r\nUser-Agent: a-very-slow-client\r\nAccept: */*\r\n\r\n";
    let mut next = rest.iter();
    let mut tick = tokio::time::interval(TRICKLE_EVERY);
    let mut buffer = [0; 1024];
    loop {
        tokio::select! {
            read = stream.read(&mut buffer) => match read {
                Ok(0) | Err(_) => return connected.elapsed(),
                // Whatever the server says on its way out (a 408), it must then close.
                Ok(_) => continue,
            },
            _ = tick.tick() => {
                let byte = next.next().expect("the server cut the client off before it finished");
                if stream.write_all(&[*byte]).await.is_err() {
                    return connected.elapsed();
                }
            }
        }
    }
}

#[tokio::test]
async fn a_client_trickling_its_headers_is_cut_off_while_others_are_served() {
    let served = serve(transport(64)).await;
    let connected = Instant::now();
    let slow = half_a_request(served.address).await;
    let cut_off = tokio::spawn(trickle_until_cut_off(slow, connected));

    let client = reqwest::Client::new();
    let mut pace = tokio::time::interval(Duration::from_millis(100));
    let (mut served_meanwhile, mut slowest) = (0, Duration::ZERO);
    while !cut_off.is_finished() {
        pace.tick().await;
        let asked = Instant::now();
        let response = client.get(format!("{}/healthz", served.url)).send().await.unwrap();
        assert_eq!(response.status(), 200);
        slowest = slowest.max(asked.elapsed());
        served_meanwhile += 1;
    }
    let cut_off = cut_off.await.unwrap();
    eprintln!(
        "slow client cut off after {cut_off:.2?} (header timeout {HEADER_TIMEOUT:?}); \
         {served_meanwhile} requests served meanwhile, slowest {slowest:.2?}"
    );
    assert!(cut_off >= HEADER_TIMEOUT - Duration::from_millis(100), "{cut_off:?}");
    assert!(cut_off < HEADER_TIMEOUT + Duration::from_millis(1500), "{cut_off:?}");
    assert!(served_meanwhile >= 5, "other clients were served while the slow one trickled");
    assert!(slowest < Duration::from_secs(1), "nobody waited on the slow client: {slowest:?}");
}

#[tokio::test]
async fn an_idle_keep_alive_connection_is_closed_after_the_header_timeout() {
    let served = serve(transport(64)).await;
    let mut stream = TcpStream::connect(served.address).await.unwrap();
    stream.write_all(b"GET /healthz HTTP/1.1\r\nHost: registry\r\n\r\n").await.unwrap();
    let mut answer = Vec::new();
    let mut buffer = [0; 4096];
    while !String::from_utf8_lossy(&answer).contains("\"ok\"") {
        let n = stream.read(&mut buffer).await.unwrap();
        assert!(n > 0, "the server answered before closing");
        answer.extend_from_slice(&buffer[..n]);
    }
    assert!(answer.starts_with(b"HTTP/1.1 200"));
    let answered = Instant::now();
    let read = tokio::time::timeout(HEADER_TIMEOUT * 3, stream.read(&mut buffer)).await;
    let idle = answered.elapsed();
    assert!(matches!(read, Ok(Ok(0)) | Ok(Err(_))), "the server closed the idle connection");
    eprintln!("idle keep-alive connection closed after {idle:.2?}");
    assert!(idle >= HEADER_TIMEOUT - Duration::from_millis(100), "{idle:?}");
}

#[tokio::test]
async fn connections_beyond_the_cap_wait_until_one_closes() {
    let served = serve(transport(2)).await;
    // Both slots go to clients that never finish their request.
    let _hogs = [half_a_request(served.address).await, half_a_request(served.address).await];
    let asked = Instant::now();
    let response = reqwest::get(format!("{}/healthz", served.url)).await.unwrap();
    let waited = asked.elapsed();
    assert_eq!(response.status(), 200);
    eprintln!("the third client was served after {waited:.2?}, when a slot was freed");
    assert!(waited >= HEADER_TIMEOUT - Duration::from_millis(300), "{waited:?}");
    assert!(waited < HEADER_TIMEOUT + Duration::from_secs(2), "{waited:?}");
}

#[tokio::test]
async fn shutdown_ends_change_feed_streams_and_idle_connections_and_returns() {
    let mut served = serve(transport(64)).await;
    // An idle keep-alive connection and an open change feed must not hold up the shutdown.
    let client = reqwest::Client::new();
    assert_eq!(client.get(format!("{}/healthz", served.url)).send().await.unwrap().status(), 200);
    let token = served.admin.clone();
    let mut feed = client
        .get(format!("{}/api/v1/events", served.url))
        .bearer_auth(&token)
        .send()
        .await
        .unwrap();
    assert_eq!(feed.status(), 200);

    let asked = Instant::now();
    tokio::time::timeout(Duration::from_secs(10), served.stop())
        .await
        .expect("serve returned after shutdown");
    eprintln!("shutdown took {:.2?}", asked.elapsed());
    let ended = tokio::time::timeout(Duration::from_secs(5), async {
        while let Ok(Some(_)) = feed.chunk().await {}
    })
    .await;
    assert!(ended.is_ok(), "the change feed stream ended");
    assert!(
        client.get(format!("{}/healthz", served.url)).send().await.is_err(),
        "nothing listens anymore"
    );
}

/// A self-signed certificate for `localhost` and its key, as PEM files.
fn self_signed(dir: &Path, name: &str) -> (PathBuf, PathBuf, String) {
    let made = rcgen::generate_simple_self_signed(vec!["localhost".to_owned()]).unwrap();
    let (cert, key) = (dir.join(format!("{name}.crt")), dir.join(format!("{name}.key")));
    std::fs::write(&cert, made.cert.pem()).unwrap();
    std::fs::write(&key, made.signing_key.serialize_pem()).unwrap();
    (cert, key, made.cert.pem())
}

/// GET `path` over TLS, trusting only `root_pem`; the status, or the error that stopped it.
async fn https_get(address: SocketAddr, root_pem: &str, path: &str) -> Result<u16, String> {
    use rustls::pki_types::pem::PemObject;
    let mut roots = rustls::RootCertStore::empty();
    roots
        .add(rustls::pki_types::CertificateDer::from_pem_slice(root_pem.as_bytes()).unwrap())
        .unwrap();
    let provider = Arc::new(rustls::crypto::aws_lc_rs::default_provider());
    let config = rustls::ClientConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()
        .unwrap()
        .with_root_certificates(roots)
        .with_no_client_auth();
    let connector = tokio_rustls::TlsConnector::from(Arc::new(config));
    let tcp = TcpStream::connect(address).await.map_err(|e| e.to_string())?;
    let name = rustls::pki_types::ServerName::try_from("localhost").unwrap();
    let tls = connector.connect(name, tcp).await.map_err(|e| format!("handshake: {e}"))?;
    let (mut sender, connection) = hyper::client::conn::http1::handshake(TokioIo::new(tls))
        .await
        .map_err(|e| e.to_string())?;
    tokio::spawn(connection);
    let request = hyper::Request::get(path)
        .header("host", format!("localhost:{}", address.port()))
        .body(Empty::<Bytes>::new())
        .unwrap();
    let response = sender.send_request(request).await.map_err(|e| e.to_string())?;
    let status = response.status().as_u16();
    response.into_body().collect().await.map_err(|e| e.to_string())?;
    Ok(status)
}

#[tokio::test]
async fn serves_https_with_the_operators_certificate_and_not_plain_http() {
    let dir = tempfile::tempdir().unwrap();
    let (cert, key, cert_pem) = self_signed(dir.path(), "registry");
    let tls = TlsIdentity::load(&cert, &key).unwrap();
    let served = serve(Transport { tls: Some(tls), ..transport(64) }).await;

    assert_eq!(https_get(served.address, &cert_pem, "/healthz").await, Ok(200));
    let (_, _, stranger) = self_signed(dir.path(), "stranger");
    let refused = https_get(served.address, &stranger, "/healthz").await;
    assert!(refused.is_err_and(|e| e.contains("handshake")), "only the trusted certificate works");
    let plain = reqwest::get(format!("{}/healthz", served.url)).await;
    assert!(plain.is_err(), "plain HTTP to the TLS port fails: {plain:?}");
}

/// `pps-server serve` with these flags on `dir`'s database, or what it said when it refused.
fn serve_binary(dir: &Path, flags: &[&str]) -> Result<Registry, String> {
    Registry::try_on_database(&dir.join("pps.db"), flags)
}

#[tokio::test]
async fn the_binary_serves_https_and_explains_bad_tls_settings() {
    let dir = tempfile::tempdir().unwrap();
    let (cert, key, cert_pem) = self_signed(dir.path(), "registry");
    let (_, other_key, _) = self_signed(dir.path(), "other");
    let flag = |name: &str, path: &Path| [name.to_owned(), path.to_str().unwrap().to_owned()];

    let tls = [flag("--tls-cert", &cert), flag("--tls-key", &key)].concat();
    let served = serve_binary(dir.path(), &tls.iter().map(String::as_str).collect::<Vec<_>>());
    let served = served.unwrap();
    let url = &served.url;
    assert!(url.starts_with("https://127.0.0.1:"), "the banner shows an https URL: {url}");
    let address: SocketAddr = url.trim_start_matches("https://").parse().unwrap();
    assert_eq!(https_get(address, &cert_pem, "/healthz").await, Ok(200));

    let other_dir = tempfile::tempdir().unwrap();
    let refused = |args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        serve_binary(other_dir.path(), &args).expect_err("the server refuses to start")
    };
    let half = refused(flag("--tls-cert", &cert).to_vec());
    assert!(half.contains("--tls-cert and --tls-key") && half.contains("both"), "{half}");
    let missing = dir.path().join("missing.key");
    let unreadable = refused([flag("--tls-cert", &cert), flag("--tls-key", &missing)].concat());
    assert!(
        unreadable.contains("cannot read the TLS private key")
            && unreadable.contains("missing.key"),
        "{unreadable}"
    );
    let not_a_key = refused([flag("--tls-cert", &cert), flag("--tls-key", &cert)].concat());
    assert!(not_a_key.contains("holds no private key"), "{not_a_key}");
    let mismatched = refused([flag("--tls-cert", &cert), flag("--tls-key", &other_key)].concat());
    assert!(mismatched.contains("does not belong to the certificate"), "{mismatched}");
}

#[tokio::test]
async fn the_binary_refuses_durations_it_cannot_count_with_their_range() {
    let dir = tempfile::tempdir().unwrap();
    let flags = ["--header-timeout", "--body-timeout", "--write-timeout"];
    for (flag, value) in flags.iter().flat_map(|f| [(*f, "18446744073709551615"), (*f, "0")]) {
        let said =
            serve_binary(dir.path(), &[flag, value]).expect_err("the server refuses to start");
        assert!(
            said.contains(flag) && said.contains("1 to 3600 seconds"),
            "{flag} {value}: {said}"
        );
    }
    let said = serve_binary(dir.path(), &["--task-lease", "1e300"])
        .expect_err("the server refuses to start");
    assert!(said.contains("0.5 to 3600 seconds"), "{said}");
    assert!(!dir.path().join("pps.db").exists(), "a refused start leaves no database");
}
