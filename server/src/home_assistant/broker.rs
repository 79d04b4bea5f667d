//! The broker the bridge talks to, as `--mqtt` names it: `mqtt://[USER[:PASS]@]HOST[:PORT]`,
//! or `mqtts://` for MQTT over TLS.

use std::fmt;
use std::str::FromStr;

/// MQTT's registered ports for plain TCP and for TLS.
const MQTT_PORT: u16 = 1883;
const MQTTS_PORT: u16 = 8883;

/// A broker address with its optional login.
#[derive(Clone, PartialEq, Eq)]
pub struct Broker {
    pub host: String,
    pub port: u16,
    /// User name and password, percent-decoded.
    pub login: Option<(String, String)>,
    /// `mqtts://`: spoken over TLS, the broker's certificate checked.
    pub tls: bool,
}

// By hand: the password never reaches a log line.
impl fmt::Debug for Broker {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Broker")
            .field("host", &self.host)
            .field("port", &self.port)
            .field("user", &self.login.as_ref().map(|(user, _)| user))
            .field("tls", &self.tls)
            .finish()
    }
}

impl fmt::Display for Broker {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let scheme = if self.tls { "mqtts" } else { "mqtt" };
        // IPv6 literals are bracketed again, so that the port stays readable.
        let host =
            if self.host.contains(':') { format!("[{}]", self.host) } else { self.host.clone() };
        match &self.login {
            Some((user, _)) => write!(f, "{scheme}://{user}@{host}:{}", self.port),
            None => write!(f, "{scheme}://{host}:{}", self.port),
        }
    }
}

impl FromStr for Broker {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        const EXAMPLE: &str = "e.g. mqtt://user:password@homeassistant.local:1883";
        let url = url::Url::parse(text)
            .map_err(|error| format!("{text:?} is not a broker URL ({error}); {EXAMPLE}"))?;
        let (tls, default_port) = match url.scheme() {
            "mqtt" => (false, MQTT_PORT),
            "mqtts" => (true, MQTTS_PORT),
            other => {
                return Err(format!(
                    "a broker URL starts with mqtt:// or mqtts://, not {other}://; {EXAMPLE}"
                ));
            }
        };
        let host = url
            .host_str()
            .filter(|host| !host.is_empty())
            .ok_or_else(|| format!("{text:?} names no broker host; {EXAMPLE}"))?;
        // IPv6 literals come bracketed; the socket address wants them bare.
        let host = host.trim_start_matches('[').trim_end_matches(']').to_owned();
        if tls && rustls::pki_types::ServerName::try_from(host.as_str()).is_err() {
            return Err(format!(
                "{host:?} cannot be checked against a TLS certificate: give the broker's DNS \
                 name or IP address"
            ));
        }
        if !matches!(url.path(), "" | "/") || url.query().is_some() || url.fragment().is_some() {
            return Err(format!(
                "{text:?} has a path or query; a broker URL is only mqtt://[USER:PASS@]HOST[:PORT]"
            ));
        }
        let decode = |part: &str| {
            url::form_urlencoded::parse(format!("x={}", part.replace('+', "%2B")).as_bytes())
                .next()
                .map(|(_, value)| value.into_owned())
                .unwrap_or_default()
        };
        let login = match (url.username(), url.password()) {
            ("", None) => None,
            ("", Some(_)) => {
                return Err(format!("{text:?} has a password but no user name; {EXAMPLE}"));
            }
            (user, password) => Some((decode(user), password.map(decode).unwrap_or_default())),
        };
        Ok(Self { host, port: url.port().unwrap_or(default_port), login, tls })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plain_host_takes_the_mqtt_port() {
        let broker: Broker = "mqtt://127.0.0.1".parse().unwrap();
        assert_eq!(
            broker,
            Broker { host: "127.0.0.1".into(), port: 1883, login: None, tls: false }
        );
        assert_eq!(broker.to_string(), "mqtt://127.0.0.1:1883");
    }

    #[test]
    fn mqtts_speaks_tls_on_the_mqtts_port() {
        let broker: Broker = "mqtts://ha:secret@broker.lan".parse().unwrap();
        assert!(broker.tls);
        assert_eq!((broker.host.as_str(), broker.port), ("broker.lan", 8883));
        assert_eq!(broker.to_string(), "mqtts://ha@broker.lan:8883");
        let broker: Broker = "mqtts://[::1]:18883".parse().unwrap();
        assert_eq!(broker.to_string(), "mqtts://[::1]:18883");
    }

    #[test]
    fn a_login_is_decoded_and_never_shown() {
        let broker: Broker = "mqtt://ha%20user:p%40ss+w@broker.lan:8883/".parse().unwrap();
        assert_eq!(broker.host, "broker.lan");
        assert_eq!(broker.port, 8883);
        assert_eq!(broker.login, Some(("ha user".into(), "p@ss+w".into())));
        assert!(!format!("{broker} {broker:?}").contains("p@ss"), "{broker:?}");
    }

    #[test]
    fn ipv6_literals_lose_their_brackets() {
        let broker: Broker = "mqtt://[::1]:1884".parse().unwrap();
        assert_eq!((broker.host.as_str(), broker.port), ("::1", 1884));
    }

    #[test]
    fn what_is_not_a_plain_broker_url_is_refused_in_words() {
        for (text, says) in [
            ("http://broker", "starts with mqtt:// or mqtts://"),
            ("broker:1883", "starts with mqtt:// or mqtts://"),
            ("mqtts://bad_name!", "cannot be checked against a TLS certificate"),
            ("mqtt://", "names no broker host"),
            ("mqtt://broker/topic", "has a path"),
            ("mqtt://:secret@broker", "no user name"),
            ("not a url", "is not a broker URL"),
        ] {
            let error = text.parse::<Broker>().unwrap_err();
            assert!(error.contains(says), "{text}: {error}");
        }
    }
}
