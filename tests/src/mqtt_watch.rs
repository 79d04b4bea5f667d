//! A plain MQTT client for tests: it remembers the last message on every topic it subscribed
//! to (retained ones included) and publishes what the test says, as another device on the
//! broker would.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime};

use rumqttc::{AsyncClient, Event, MqttOptions, Packet, QoS};

use pps_test_kit::wait;

/// The last payload on each topic, and when it arrived.
type Seen = Arc<Mutex<HashMap<String, (Vec<u8>, SystemTime)>>>;

/// A connected client and the last payload seen on each topic.
#[derive(Debug)]
pub struct MqttWatch {
    client: AsyncClient,
    seen: Seen,
    task: tokio::task::JoinHandle<()>,
}

impl MqttWatch {
    /// Connects to the broker on `port` as `id` and subscribes to `filters`.
    pub async fn connect(port: u16, id: &str, filters: &[&str]) -> Self {
        let mut options = MqttOptions::new(id, "127.0.0.1", port);
        // More than the bridge takes (1 MiB) both ways, to see the bridge refuse what this
        // client sends and takes in itself.
        options.set_keep_alive(Duration::from_secs(30)).set_max_packet_size(4 << 20, 4 << 20);
        let (client, mut eventloop) = AsyncClient::new(options, 256);
        let seen: Seen = Arc::default();
        let kept = seen.clone();
        let task = tokio::spawn(async move {
            loop {
                match eventloop.poll().await {
                    Ok(Event::Incoming(Packet::Publish(publish))) => {
                        kept.lock().unwrap_or_else(|e| e.into_inner()).insert(
                            publish.topic.clone(),
                            (publish.payload.to_vec(), SystemTime::now()),
                        );
                    }
                    Ok(_) => {}
                    // The test's broker went away on purpose; try again until it is back.
                    Err(_) => {
                        #[allow(clippy::disallowed_methods, reason = "a real broker's back-off")]
                        tokio::time::sleep(Duration::from_millis(100)).await;
                    }
                }
            }
        });
        for filter in filters {
            client.subscribe(*filter, QoS::AtLeastOnce).await.expect("the subscription is queued");
        }
        Self { client, seen, task }
    }

    /// The last payload on `topic`, if any came.
    pub fn last(&self, topic: &str) -> Option<Vec<u8>> {
        let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        seen.get(topic).map(|(payload, _)| payload.clone())
    }

    /// When the last payload on `topic` arrived (for figures such as "trial to state").
    pub fn arrived(&self, topic: &str) -> Option<SystemTime> {
        let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        seen.get(topic).map(|(_, at)| *at)
    }

    /// The last payload on `topic` as text.
    pub fn text(&self, topic: &str) -> Option<String> {
        self.last(topic).map(|bytes| String::from_utf8_lossy(&bytes).into_owned())
    }

    /// Every topic with a payload, matching `keep`.
    pub fn topics(&self, keep: impl Fn(&str) -> bool) -> Vec<String> {
        let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        let mut topics: Vec<String> = seen
            .iter()
            .filter(|(topic, (payload, _))| !payload.is_empty() && keep(topic))
            .map(|(topic, _)| topic.clone())
            .collect();
        topics.sort();
        topics
    }

    /// Waits until `topic` carries `payload`.
    pub async fn until_text(&self, topic: &str, payload: &str) {
        wait::until(&format!("{payload:?} on {topic}"), || async {
            (self.text(topic).as_deref() == Some(payload)).then_some(())
        })
        .await;
    }

    /// Publishes `payload` on `topic`, not retained, at most once.
    pub async fn publish(&self, topic: &str, payload: impl Into<Vec<u8>>) {
        self.client
            .publish(topic, QoS::AtMostOnce, false, payload.into())
            .await
            .expect("the publish is queued");
    }
}

impl Drop for MqttWatch {
    fn drop(&mut self) {
        self.task.abort();
    }
}
