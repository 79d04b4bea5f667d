//! The Home Assistant bridge: every active tag as a device in Home Assistant over MQTT
//! discovery, its actions as buttons whose presses become tasks, its state as the robots'
//! success detectors last saw it. Off unless `serve --mqtt` names a broker.
//!
//! It learns of changes from the change feed, so edits made on any replica reach Home
//! Assistant, and of several replicas only the holder of the bridge's lease runs it. It never
//! says a device is in a state because a button was pressed: only trials say that.

mod bridge;
mod broker;
mod connection;
mod device;
mod discovery;
mod lease;
mod press;
mod replicas;
mod task_words;
mod tls_relay;
mod trust;
mod two_state;

use std::path::Path;
use std::time::Duration;

pub use broker::Broker;
pub use replicas::start;
pub use trust::BrokerTrust;

/// The name of the caretaker credential presses are asked with; revoking it refuses them.
pub const CREDENTIAL: &str = "Home Assistant bridge";
pub const DEFAULT_PREFIX: &str = "homeassistant";

/// How the bridge reaches Home Assistant.
#[derive(Debug, Clone)]
pub struct Config {
    pub broker: Broker,
    /// The CAs the broker's certificate is checked against, for `mqtts://` only.
    pub tls: Option<BrokerTrust>,
    /// Home Assistant's discovery prefix.
    pub prefix: String,
    /// The MQTT client id; a random one per process when not given.
    pub client_id: String,
}

impl Config {
    /// The bridge to `broker` under `prefix`, as `client_id` or a fresh random id. An
    /// `mqtts://` broker's certificate must chain to the CA in `ca_file`, or without one to a
    /// CA the system trusts.
    pub fn new(
        broker: Broker,
        ca_file: Option<&Path>,
        prefix: String,
        client_id: Option<String>,
    ) -> anyhow::Result<Self> {
        let tls = match (broker.tls, ca_file) {
            (true, Some(file)) => Some(BrokerTrust::ca_file(file)?),
            (true, None) => Some(BrokerTrust::system()?),
            (false, None) => None,
            (false, Some(_)) => anyhow::bail!(
                "--mqtt-ca (PPS_MQTT_CA) is for a broker spoken to over TLS: give an mqtts:// \
                 broker URL, or leave the CA out for {broker}"
            ),
        };
        let client_id = client_id.unwrap_or_else(|| {
            // MQTT 3.1.1 brokers must accept ids of up to 23 characters; this is 21.
            format!("pps-registry-{:08x}", rand::random::<u32>())
        });
        Ok(Self { broker, tls, prefix, client_id })
    }
}

/// Checks a discovery prefix: topic levels without wildcards, and not empty.
pub fn parse_prefix(text: &str) -> Result<String, String> {
    let bad = text.is_empty()
        || text.starts_with('/')
        || text.ends_with('/')
        || text.contains(['+', '#', '\0'])
        || text.split('/').any(str::is_empty);
    if bad {
        return Err(format!(
            "{text:?} is not a discovery prefix: one or more MQTT topic levels such as \
             {DEFAULT_PREFIX}, without + or # and without empty levels"
        ));
    }
    Ok(text.to_owned())
}

/// Checks an MQTT client id: 1 to 64 visible characters.
pub fn parse_client_id(text: &str) -> Result<String, String> {
    if text.is_empty() || text.chars().count() > 64 || text.chars().any(|c| c.is_control()) {
        return Err(format!(
            "{text:?} is not a client id: 1 to 64 characters, no control characters"
        ));
    }
    Ok(text.to_owned())
}

/// How long a stopping server waits for the bridge to mark its devices unavailable.
pub const GOODBYE_WITHIN: Duration = Duration::from_secs(3);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_are_plain_topic_levels() {
        assert_eq!(parse_prefix("homeassistant").unwrap(), "homeassistant");
        assert_eq!(parse_prefix("home/assistant").unwrap(), "home/assistant");
        for bad in ["", "/ha", "ha/", "ha/+", "#", "a//b"] {
            assert!(parse_prefix(bad).unwrap_err().contains("not a discovery prefix"), "{bad}");
        }
    }

    #[test]
    fn client_ids_are_short_and_visible() {
        assert!(parse_client_id("registry-1").is_ok());
        assert!(parse_client_id("").is_err());
        assert!(parse_client_id(&"x".repeat(65)).is_err());
        let random =
            Config::new("mqtt://h".parse().unwrap(), None, DEFAULT_PREFIX.into(), None).unwrap();
        assert!(random.client_id.len() <= 23, "{}", random.client_id);
    }
}
