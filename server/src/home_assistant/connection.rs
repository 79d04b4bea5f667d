//! The bridge's connection to the broker: a fresh session with the bridge's last will, polled
//! in a task of its own that reconnects with growing, jittered waits and reports what happens.

use std::time::Duration;

use backon::{BackoffBuilder, ExponentialBuilder};
use rumqttc::{AsyncClient, Event, LastWill, MqttOptions, Packet, QoS};
use tokio::sync::mpsc;
use tokio::time::Instant;

use super::Config;
use super::discovery;

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
    Lost,
    Message { topic: String, payload: bytes::Bytes },
}

/// Connects as `config` says: the client to publish with, what the connection reports, and
/// the task polling it (it ends once the client disconnects).
pub fn open(
    config: &Config,
) -> (AsyncClient, mpsc::UnboundedReceiver<Link>, tokio::task::JoinHandle<()>) {
    let mut options = MqttOptions::new(&config.client_id, &config.broker.host, config.broker.port);
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
    let (client, eventloop) = AsyncClient::new(options, QUEUE);
    let (links, link) = mpsc::unbounded_channel();
    let connection = tokio::spawn(drive(eventloop, links, config.broker.to_string()));
    (client, link, connection)
}

/// Polls the connection, reconnecting with backoff and jitter, until the client disconnects.
async fn drive(
    mut eventloop: rumqttc::EventLoop,
    links: mpsc::UnboundedSender<Link>,
    broker: String,
) {
    let mut waits = reconnect_waits();
    let mut down_since: Option<Instant> = None;
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
                if down_since.is_none() {
                    // Once per outage; the registry goes on serving meanwhile.
                    tracing::warn!(%broker, %error, "lost the MQTT broker; reconnecting");
                    down_since = Some(Instant::now());
                    let _ = links.send(Link::Lost);
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

/// A fresh, endless sequence of jittered waits between reconnection attempts.
fn reconnect_waits() -> impl Iterator<Item = Duration> {
    ExponentialBuilder::new()
        .with_min_delay(FIRST_BACKOFF)
        .with_max_delay(MAX_BACKOFF)
        .with_jitter()
        .without_max_times()
        .build()
}
