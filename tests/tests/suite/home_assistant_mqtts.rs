//! The Home Assistant bridge over `mqtts://` against a real Mosquitto speaking TLS with a
//! certificate from a CA the test made, as a home broker's own CA is: discovery and presses
//! over TLS, the CA given with `--mqtt-ca` or trusted by the system, and each way a broker can
//! fail the check said in one sentence while the bridge keeps trying.

use std::path::Path;
use std::time::Instant;

use pps_test_kit::{ADA_SWITCH, Registry, wait};
use pps_tests::{Mosquitto, MqttWatch, TestCa};
use serde_json::json;

const BRIDGE: &str = "pps/bridge/availability";

/// Waits until the test's own client (on the broker's plain port) sees every seeded tag.
async fn announced(watch: &MqttWatch) {
    wait::until("the five seeded tags announced", || async {
        let configs =
            watch.topics(|t| t.starts_with("homeassistant/") && t.ends_with("/task/config"));
        (configs.len() == 5).then_some(())
    })
    .await;
}

/// A registry bridging over `mqtts://`: its TLS socket goes into `files`, which the test
/// removes, since a registry killed outright leaves it behind.
fn serve_tls(flags: &[&str], files: &Path, env: &[(&str, &str)]) -> Registry {
    let tmp = files.to_str().expect("a UTF-8 temporary directory");
    let env: Vec<(&str, &str)> = env.iter().copied().chain([("TMPDIR", tmp)]).collect();
    Registry::with_flags_and_env(flags, &env)
}

async fn logged(registry: &Registry, sentence: &str) {
    wait::until(&format!("the log to say {sentence:?}"), || async {
        registry.logged(sentence).then_some(())
    })
    .await;
}

#[tokio::test]
async fn discovery_presses_and_the_last_will_go_over_tls_to_a_broker_with_its_own_ca() {
    let ca = TestCa::new("home broker CA");
    let broker = Mosquitto::start_tls(&ca.server(&["127.0.0.1"])).await;
    let files = tempfile::tempdir().unwrap();
    let ca_file = ca.write(files.path(), "home-ca.pem");
    let started = Instant::now();
    let registry = serve_tls(
        &["--mqtt", &broker.tls_url(), "--mqtt-ca", ca_file.to_str().unwrap()],
        files.path(),
        &[],
    );
    let watch = MqttWatch::connect(broker.port, "watch-tls", &["homeassistant/#", "pps/#"]).await;
    announced(&watch).await;
    watch.until_text(BRIDGE, "online").await;
    eprintln!(
        "serve started to five tags announced over TLS: {} ms",
        started.elapsed().as_millis()
    );
    assert_eq!(
        registry.get("/api/v1/home-assistant").await,
        json!({
            "bridge": "connected",
            "broker": broker.tls_url(),
            "prefix": "homeassistant",
            "problem": null,
        })
    );

    // A press goes the other way through the same TLS connection.
    let ada = format!("pps_{}", ADA_SWITCH.to_ascii_lowercase());
    let pressed = Instant::now();
    watch.publish(&format!("pps/{ada}/press/off"), "PRESS").await;
    let task = wait::until("the press to become a task", || async {
        let page = registry.get(&format!("/api/v1/tasks?epc={ADA_SWITCH}")).await;
        page["items"].as_array().and_then(|items| items.first().cloned())
    })
    .await;
    eprintln!("press to task over TLS: {} ms", pressed.elapsed().as_millis());
    assert_eq!(
        (task["action"].as_str(), task["created_by"].as_str()),
        (Some("off"), Some("Home Assistant bridge"))
    );

    // Killed outright, the registry leaves its last will to the broker, over TLS as well.
    drop(registry);
    watch.until_text(BRIDGE, "offline").await;
}

#[tokio::test]
async fn the_systems_cas_are_trusted_unless_a_ca_file_is_given() {
    let home = TestCa::new("home broker CA");
    let other = TestCa::new("some other CA");
    let broker = Mosquitto::start_tls(&home.server(&["127.0.0.1"])).await;
    let files = tempfile::tempdir().unwrap();
    let home_file = home.write(files.path(), "home-ca.pem");
    let other_file = other.write(files.path(), "other-ca.pem");
    let mqtts = ["--mqtt", &broker.tls_url()];

    // "The system" is whatever SSL_CERT_FILE names, as with OpenSSL.
    let trusting =
        serve_tls(&mqtts, files.path(), &[("SSL_CERT_FILE", home_file.to_str().unwrap())]);
    let refusing =
        serve_tls(&mqtts, files.path(), &[("SSL_CERT_FILE", other_file.to_str().unwrap())]);
    wait::until("the bridge trusting the system's CA to connect", || async {
        (trusting.get("/api/v1/home-assistant").await["bridge"] == "connected").then_some(())
    })
    .await;
    logged(
        &refusing,
        &format!(
            "the MQTT broker at {} shows a certificate not signed by a CA this system trusts: \
             give the CA that signed it with --mqtt-ca FILE (PPS_MQTT_CA)",
            broker.tls_url()
        ),
    )
    .await;
    assert_eq!(refusing.get("/api/v1/home-assistant").await["bridge"], "connecting");
}

#[tokio::test]
async fn a_broker_signed_by_another_ca_is_refused_in_words_until_it_shows_the_right_one() {
    let home = TestCa::new("home broker CA");
    let other = TestCa::new("some other CA");
    let mut broker = Mosquitto::start_tls(&other.server(&["127.0.0.1"])).await;
    let files = tempfile::tempdir().unwrap();
    let ca_file = home.write(files.path(), "home-ca.pem");
    let registry = serve_tls(
        &["--mqtt", &broker.tls_url(), "--mqtt-ca", ca_file.to_str().unwrap()],
        files.path(),
        &[],
    );
    let refused = format!(
        "the MQTT broker at {} shows a certificate not signed by the CA in {}: give the CA that \
         signed it with --mqtt-ca (PPS_MQTT_CA)",
        broker.tls_url(),
        ca_file.display()
    );
    logged(&registry, &refused).await;
    // The admin page says it too.
    let said = json!({
        "bridge": "connecting",
        "broker": broker.tls_url(),
        "prefix": "homeassistant",
        "problem": refused,
    });
    wait::until("the bridge's status to say why", || async {
        (registry.get("/api/v1/home-assistant").await == said).then_some(())
    })
    .await;
    assert_eq!(registry.get("/api/v1/tags").await["items"].as_array().map(Vec::len), Some(5));

    // The broker gets the certificate its owner meant; the bridge, still trying, connects.
    broker.set_identity(&home.server(&["127.0.0.1"]));
    broker.restart().await;
    let back = Instant::now();
    let watch =
        MqttWatch::connect(broker.port, "watch-right-ca", &["homeassistant/#", BRIDGE]).await;
    announced(&watch).await;
    watch.until_text(BRIDGE, "online").await;
    eprintln!("right certificate to five tags announced: {} ms", back.elapsed().as_millis());
    assert_eq!(registry.get("/api/v1/home-assistant").await["problem"], json!(null));
}

#[tokio::test]
async fn a_certificate_for_another_name_an_expired_one_and_a_plain_port_are_refused_in_words() {
    let ca = TestCa::new("home broker CA");
    let broker = Mosquitto::start_tls(&ca.server(&["broker.example"])).await;
    let outdated = Mosquitto::start_tls(&ca.expired_server(&["127.0.0.1"])).await;
    let files = tempfile::tempdir().unwrap();
    let ca_file = ca.write(files.path(), "home-ca.pem");
    let ca_file = ca_file.to_str().unwrap();
    let wrong_name =
        serve_tls(&["--mqtt", &broker.tls_url(), "--mqtt-ca", ca_file], files.path(), &[]);
    let plain = format!("mqtts://127.0.0.1:{}", broker.port);
    let not_tls = serve_tls(&["--mqtt", &plain, "--mqtt-ca", ca_file], files.path(), &[]);
    let expired =
        serve_tls(&["--mqtt", &outdated.tls_url(), "--mqtt-ca", ca_file], files.path(), &[]);
    logged(
        &wrong_name,
        "the MQTT broker's certificate is not for \"127.0.0.1\": connect to a name its \
         certificate lists, or give the broker a certificate for this name",
    )
    .await;
    let port = broker.port;
    logged(
        &not_tls,
        &format!(
            "the MQTT broker at {plain} does not speak TLS on port {port}: use \
             mqtt://127.0.0.1:{port} if that port is plain MQTT, or the broker's TLS port \
             (usually 8883)"
        ),
    )
    .await;
    logged(
        &expired,
        &format!(
            "the MQTT broker at {} shows an expired certificate: renew it on the broker",
            outdated.tls_url()
        ),
    )
    .await;
}

#[tokio::test]
async fn a_plain_url_for_the_tls_port_is_told_to_use_mqtts() {
    let ca = TestCa::new("home broker CA");
    let broker = Mosquitto::start_tls(&ca.server(&["127.0.0.1"])).await;
    let port = broker.tls_port.unwrap();
    let registry = Registry::with_flags(&["--mqtt", &format!("mqtt://127.0.0.1:{port}")]);
    logged(
        &registry,
        &format!(
            "the MQTT broker at mqtt://127.0.0.1:{port} hung up before answering the bridge's \
             CONNECT: if that port speaks TLS, use mqtts://127.0.0.1:{port}; otherwise its log \
             says why it refused"
        ),
    )
    .await;
}

#[test]
fn a_ca_file_the_bridge_cannot_use_stops_serve_in_one_sentence() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("pps.db");
    let missing = dir.path().join("missing.pem");
    let empty = dir.path().join("empty.pem");
    std::fs::write(&empty, "no certificate here\n").unwrap();
    let (missing, empty) = (missing.to_str().unwrap(), empty.to_str().unwrap());
    for (flags, says) in [
        (
            vec!["--mqtt", "mqtts://broker.lan", "--mqtt-ca", missing],
            format!("cannot read the MQTT broker's CA file {missing}"),
        ),
        (
            vec!["--mqtt", "mqtts://broker.lan", "--mqtt-ca", empty],
            format!("{empty} holds no certificate (no -----BEGIN CERTIFICATE----- block)"),
        ),
        (
            vec!["--mqtt", "mqtt://broker.lan", "--mqtt-ca", empty],
            "--mqtt-ca (PPS_MQTT_CA) is for a broker spoken to over TLS: give an mqtts:// \
             broker URL, or leave the CA out for mqtt://broker.lan:1883"
                .to_owned(),
        ),
        (
            vec!["--mqtt-ca", empty],
            "--mqtt-ca (PPS_MQTT_CA) goes with --mqtt mqtts://HOST: give the broker too".to_owned(),
        ),
    ] {
        let output = std::process::Command::new(pps_test_kit::workspace_bin("pps-server"))
            .args(["serve", "--listen", "127.0.0.1:0"])
            .args(&flags)
            .arg("--db")
            .arg(&db)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{flags:?} was accepted");
        assert!(stderr.contains(&says), "{flags:?}: {stderr}");
        assert!(!db.exists(), "{flags:?}: a refused start left a database behind");
    }
}
