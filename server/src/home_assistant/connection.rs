//! The bridge's connection to the broker: a fresh session with the bridge's last will, polled
//! in a task of its own that reconnects with growing, jittered waits and reports what happens.
//! `mqtts://` goes through the [`TlsRelay`].

use std::time::Duration;

use backon::{BackoffBuilder, ExponentialBuilder};
use rumqttc::{
    AsyncClient, ConnectionError, Event, LastWill, MqttOptions, Packet, QoS, StateError, Transport,
};
use tokio::sync::mpsc;
use tokio::time::Instant;

use super::discovery;
use super::tls_relay::TlsRelay;
use super::{Broker, Config, trust};

/// The broker declares the bridge gone (and sends its last will) after 1.5 of these.
const KEEP_ALIVE: Duration = Duration::from_secs(10);
/// Reconnecting waits this long at first, doubling to the cap, each wait jittered (the robots'
/// registry client waits the same way, with the same crate).
const FIRST_BACKOFF: Duration = Duration::from_millis(250);
const MAX_BACKOFF: Duration = Duration::from_secs(8);
/// Packets up to this size are read (and a press that big ignored, with a line in the log);
/// a bigger one ends the connection, which is then made again.
const MAX_INCOMING_PACKET: usize = 1024 * 1024;
/// Requests queued for the connection; a publish waits while it is full.
const QUEUE: usize = 1024;

/// What the connection reports to the bridge.
#[derive(Debug)]
pub enum Link {
    Connected,
    /// Cannot use the broker now, and why; said again when the reason changes.
    Lost {
        why: String,
    },
    Message {
        topic: String,
        payload: bytes::Bytes,
    },
}

/// The client to publish with, what the connection reports, and the task polling it (it ends
/// once the client disconnects).
pub type Opened = (AsyncClient, mpsc::UnboundedReceiver<Link>, tokio::task::JoinHandle<()>);

/// Connects as `config` says; fails only when the socket for TLS cannot be made.
pub fn open(config: &Config) -> std::io::Result<Opened> {
    let relay = match &config.tls {
        Some(trust) => Some(TlsRelay::start(&config.broker, trust)?),
        None => None,
    };
    let mut options = match &relay {
        Some(relay) => {
            let mut options = MqttOptions::new(&config.client_id, relay.socket(), 0);
            options.set_transport(Transport::Unix);
            options
        }
        None => MqttOptions::new(&config.client_id, &config.broker.host, config.broker.port),
    };
    options
        .set_keep_alive(KEEP_ALIVE)
        // A fresh session each time: presses sent while the bridge was away are not replayed.
        .set_clean_session(true)
        .set_max_packet_size(MAX_INCOMING_PACKET, 256 * 1024)
        .set_last_will(LastWill::new(
            discovery::BRIDGE_AVAILABILITY,
            discovery::OFFLINE,
            QoS::AtLeastOnce,
            true,
        ));
    if let Some((user, password)) = &config.broker.login {
        options.set_credentials(user, password);
    }
    let (client, mut eventloop) = AsyncClient::new(options, QUEUE);
    // Longer than the relay's own handshake limit, so that its reason arrives first.
    let mut network = eventloop.network_options();
    network.set_connection_timeout(trust::HANDSHAKE_WITHIN.as_secs() + 2);
    eventloop.set_network_options(network);
    let (links, link) = mpsc::unbounded_channel();
    let connection = tokio::spawn(drive(eventloop, links, config.broker.clone(), relay));
    Ok((client, link, connection))
}

/// Polls the connection, reconnecting with backoff and jitter, until the client disconnects.
async fn drive(
    mut eventloop: rumqttc::EventLoop,
    links: mpsc::UnboundedSender<Link>,
    broker: Broker,
    relay: Option<TlsRelay>,
) {
    let mut waits = reconnect_waits();
    // Whether the broker answered the bridge's CONNECT on this connection.
    let mut answered = false;
    let mut down_since: Option<Instant> = None;
    // What was last said about the outage: said again only when the reason changes.
    let mut said: Option<String> = None;
    loop {
        match eventloop.poll().await {
            Ok(Event::Incoming(Packet::ConnAck(_))) => {
                match down_since.take() {
                    Some(since) => tracing::info!(
                        %broker, after_ms = since.elapsed().as_millis() as u64,
                        "reconnected to the MQTT broker"
                    ),
                    None => tracing::info!(%broker, "connected to the MQTT broker"),
                }
                waits = reconnect_waits();
                answered = true;
                said = None;
                let _ = links.send(Link::Connected);
            }
            Ok(Event::Incoming(Packet::Publish(publish))) => {
                let _ = links.send(Link::Message {
                    topic: publish.topic.clone(),
                    payload: publish.payload.clone(),
                });
            }
            Ok(Event::Outgoing(rumqttc::Outgoing::Disconnect)) => return,
            Ok(_) => {}
            Err(error) => {
                if links.is_closed() {
                    return;
                }
                // The TLS relay knows better than rumqttc's "connection closed".
                let error = relay
                    .as_ref()
                    .and_then(TlsRelay::take_failure)
                    .unwrap_or_else(|| in_words(&error, &broker, answered));
                answered = false;
                if down_since.is_none() {
                    down_since = Some(Instant::now());
                }
                // Once per outage and reason; the registry goes on serving meanwhile.
                if said.as_ref() != Some(&error) {
                    tracing::warn!(%broker, %error, "cannot use the MQTT broker; reconnecting");
                    let _ = links.send(Link::Lost { why: error.clone() });
                    said = Some(error);
                }
                #[allow(
                    clippy::disallowed_methods,
                    reason = "back-off between attempts to reach the broker"
                )]
                tokio::time::sleep(waits.next().unwrap_or(MAX_BACKOFF)).await;
            }
        }
    }
}

/// rumqttc's error, in words where the bridge knows what it means; `answered` tells whether
/// the broker had answered the bridge's CONNECT on the connection that ended.
fn in_words(error: &ConnectionError, broker: &Broker, answered: bool) -> String {
    use rumqttc::mqttbytes::Error::{Io, PayloadSizeLimitExceeded};
    let hung_up = |error: &std::io::Error| {
        use std::io::ErrorKind::{ConnectionAborted, ConnectionReset, UnexpectedEof};
        matches!(error.kind(), ConnectionReset | ConnectionAborted | UnexpectedEof)
    };
    let no_answer = match error {
        ConnectionError::MqttState(StateError::ConnectionAborted)
        | ConnectionError::NotConnAck(_) => true,
        ConnectionError::MqttState(StateError::Deserialization(Io(error)))
        | ConnectionError::MqttState(StateError::Io(error))
        | ConnectionError::Io(error) => hung_up(error),
        _ => false,
    };
    // A TLS port hangs up on (or answers with an alert) a plain MQTT greeting.
    if no_answer && !answered && !broker.tls {
        let tls = Broker { login: None, tls: true, ..broker.clone() };
        return format!(
            "the MQTT broker at {broker} hung up before answering the bridge's CONNECT: if that \
             port speaks TLS, use {tls}; otherwise its log says why it refused"
        );
    }
    match error {
        ConnectionError::MqttState(StateError::Deserialization(PayloadSizeLimitExceeded(size))) => {
            format!(
                "the broker sent a message of {size} bytes, over the bridge's limit of \
                 {MAX_INCOMING_PACKET}: that ends the connection, and the bridge reconnects \
                 without it"
            )
        }
        other => other.to_string(),
    }
}

/// A fresh, endless sequence of jittered waits between reconnection attempts.
fn reconnect_waits() -> impl Iterator<Item = Duration> {
    ExponentialBuilder::new()
        .with_min_delay(FIRST_BACKOFF)
        .with_max_delay(MAX_BACKOFF)
        .with_jitter()
        .without_max_times()
        .build()
}
