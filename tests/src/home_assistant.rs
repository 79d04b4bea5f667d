//! A real Home Assistant (the PyPI release `tests/home-assistant/install` puts into
//! `target/home-assistant-venv`) for the bridge's end-to-end test: started on a free loopback
//! port with a minimal configuration in a temporary directory, onboarded through its own API,
//! its MQTT integration set up through its config-flow API.

use std::net::{Ipv4Addr, TcpListener};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use reqwest::header::CONTENT_TYPE;
use serde_json::{Value, json};
use tempfile::TempDir;

use pps_test_kit::{target_dir, wait};

/// A running Home Assistant and the access token of its owner; stopped when dropped.
#[derive(Debug)]
pub struct HomeAssistant {
    child: Child,
    /// Base URL without a trailing slash.
    pub url: String,
    token: String,
    http: reqwest::Client,
    _dir: TempDir,
}

impl HomeAssistant {
    /// Starts Home Assistant; [`HomeAssistant::ready`] waits for it and onboards its owner.
    pub fn start() -> Starting {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let port = TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
            .and_then(|listener| listener.local_addr())
            .expect("a free loopback port")
            .port();
        // The integrations an empty home needs to be onboarded and read over REST, nothing
        // that looks at the machine's network or hardware.
        std::fs::write(
            dir.path().join("configuration.yaml"),
            format!(
                "homeassistant:\n  name: PPS test home\n  latitude: 0\n  longitude: 0\n  \
                 elevation: 0\n  unit_system: metric\n  time_zone: UTC\n  country: US\n\
                 http:\n  server_host: 127.0.0.1\n  server_port: {port}\n\
                 onboarding:\napi:\nconfig:\n"
            ),
        )
        .expect("the configuration is written");
        let child = Command::new(hass_bin())
            .arg("--config")
            .arg(dir.path())
            // Its requirements were installed beforehand: nothing is fetched while testing.
            .arg("--skip-pip")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("hass starts");
        Starting { child: Some(child), url: format!("http://127.0.0.1:{port}"), dir: Some(dir) }
    }

    /// Calls Home Assistant's REST API as its owner.
    pub async fn call(&self, method: reqwest::Method, path: &str, body: Option<&Value>) -> Value {
        let mut request =
            self.http.request(method, format!("{}{path}", self.url)).bearer_auth(&self.token);
        if let Some(body) = body {
            request = request.json(body);
        }
        let response = request.send().await.expect("Home Assistant answers");
        let status = response.status();
        let text = response.text().await.expect("a body");
        assert!(status.is_success(), "{path}: {status} {text}");
        serde_json::from_str(&text).unwrap_or(Value::String(text))
    }

    /// Renders a template with Home Assistant's own template engine.
    pub async fn template(&self, template: &str) -> String {
        let body = json!({ "template": template });
        match self.call(reqwest::Method::POST, "/api/template", Some(&body)).await {
            Value::String(text) => text,
            other => other.to_string(),
        }
    }

    /// Every entity's state.
    pub async fn states(&self) -> Vec<Value> {
        let states = self.call(reqwest::Method::GET, "/api/states", None).await;
        states.as_array().cloned().unwrap_or_default()
    }

    /// The state of the entity whose friendly name is `name`, if there is one.
    pub async fn state_named(&self, name: &str) -> Option<Value> {
        self.states().await.into_iter().find(|s| s["attributes"]["friendly_name"] == name)
    }

    /// Sets up the MQTT integration on the broker at 127.0.0.1:`port` through the config
    /// flow, as a person does in Settings → Devices & services.
    pub async fn add_mqtt(&self, port: u16) {
        let flow = self
            .call(
                reqwest::Method::POST,
                "/api/config/config_entries/flow",
                Some(&json!({ "handler": "mqtt" })),
            )
            .await;
        assert_eq!(flow["step_id"], "broker", "{flow}");
        let path = format!("/api/config/config_entries/flow/{}", flow["flow_id"].as_str().unwrap());
        let broker = json!({ "broker": "127.0.0.1", "port": port });
        let done = self.call(reqwest::Method::POST, &path, Some(&broker)).await;
        assert_eq!(done["type"], "create_entry", "{done}");
    }
}

impl Drop for HomeAssistant {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Home Assistant started, not yet answering.
#[derive(Debug)]
pub struct Starting {
    child: Option<Child>,
    url: String,
    dir: Option<TempDir>,
}

impl Starting {
    /// Waits until Home Assistant answers, then onboards its owner and logs in.
    pub async fn ready(mut self) -> HomeAssistant {
        let http = reqwest::Client::new();
        let onboarding = format!("{}/api/onboarding", self.url);
        wait::wait_until(HASS_START, "Home Assistant to answer", || async {
            http.get(&onboarding).send().await.ok().filter(|r| r.status().is_success()).map(drop)
        })
        .await;
        let client_id = format!("{}/", self.url);
        let owner = json!({
            "client_id": client_id, "name": "Caretaker", "username": "caretaker",
            "password": "a test password, not a secret", "language": "en",
        });
        let created: Value = http
            .post(format!("{onboarding}/users"))
            .json(&owner)
            .send()
            .await
            .and_then(reqwest::Response::error_for_status)
            .expect("the owner is onboarded")
            .json()
            .await
            .expect("an auth code");
        let code = created["auth_code"].as_str().expect("an auth code");
        let form = format!(
            "grant_type=authorization_code&code={code}&client_id={}",
            client_id.replace(':', "%3A").replace('/', "%2F")
        );
        let tokens: Value = http
            .post(format!("{}/auth/token", self.url))
            .header(CONTENT_TYPE, "application/x-www-form-urlencoded")
            .body(form)
            .send()
            .await
            .and_then(reqwest::Response::error_for_status)
            .expect("the owner logs in")
            .json()
            .await
            .expect("tokens");
        HomeAssistant {
            child: self.child.take().expect("started once"),
            url: self.url.clone(),
            token: tokens["access_token"].as_str().expect("an access token").to_owned(),
            http,
            _dir: self.dir.take().expect("started once"),
        }
    }
}

impl Drop for Starting {
    fn drop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// Home Assistant loads a few hundred modules before it answers.
const HASS_START: std::time::Duration = std::time::Duration::from_secs(90);

/// `hass` from the virtualenv `tests/home-assistant/install` makes, or `HASS_BIN`.
fn hass_bin() -> PathBuf {
    if let Some(bin) = std::env::var_os("HASS_BIN") {
        return bin.into();
    }
    let bin = target_dir().join("home-assistant-venv/bin/hass");
    assert!(
        bin.is_file(),
        "{} is missing: run tests/home-assistant/install (tests/run does)",
        bin.display()
    );
    bin
}
