//! The bridge while this process holds its lease: connected to the broker, it announces every
//! active tag, keeps each device's availability, state and task up to date from the change
//! feed, removes archived tags, and hands presses to [`press`](super::press).

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Duration;

use pps_schema::{Epc, RobotId};
use rumqttc::{AsyncClient, QoS};
use serde_json::Value;
use tokio::sync::broadcast::error::RecvError;
use tokio::time::Instant;

use super::connection::{self, Link};
use super::device::TagDevice;
use super::discovery::{self, ButtonConfig, StateConfig, TaskConfig, Topics};
use super::lease::{Lease, RENEW_EVERY};
use super::press::Presses;
use super::{Config, task_words};
use crate::ops::bridge_status::Status;
use crate::state::AppState;
use crate::store::events::{Event as Change, EventKind};
use crate::store::tags::{self, StoredTag};
use crate::store::tasks::{self, TaskFilter};
use crate::store::{home_assistant, retired, robots};
use crate::tasks::availability;

/// How often availability is looked at again: robots come online and go quiet without events.
const AVAILABILITY_EVERY: Duration = Duration::from_secs(5);
/// A publish not taken by the connection within this means the broker is gone for now.
const PUBLISH_WAIT: Duration = Duration::from_secs(5);
/// Trials read back to find a tag's state.
const TRIALS_FOR_STATE: u32 = 20;
/// Home Assistant asks to be re-announced to when it starts; many bridges answer, so each
/// waits a little, at random.
const REANNOUNCE_WITHIN: Duration = Duration::from_secs(3);

/// Why the bridge stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    LeaseLost,
    Shutdown,
    /// The bridge could not start here (said in the log); tried again after a while.
    Unable,
}

/// A tag announced to Home Assistant.
#[derive(Debug)]
struct Announced {
    device: TagDevice,
    available: Option<bool>,
}

struct Bridge<'a> {
    state: &'a AppState,
    config: &'a Config,
    client: AsyncClient,
    connected: bool,
    /// By device id.
    devices: HashMap<String, Announced>,
    /// Device id by the tag's EPC now.
    by_epc: HashMap<String, String>,
}

/// Runs the bridge until the lease is lost or the server stops.
pub async fn run(state: &AppState, config: &Config, lease: &Lease) -> Ended {
    state.home_assistant.set(Status::Connecting);
    super::press::mint_credential_once(state).await;
    let (client, mut link, connection) = match connection::open(config) {
        Ok(opened) => opened,
        Err(error) => {
            tracing::warn!(%error, "cannot make the socket for TLS to the MQTT broker");
            state.home_assistant.set(Status::Standby);
            return Ended::Unable;
        }
    };
    let mut bridge = Bridge {
        state,
        config,
        client,
        connected: false,
        devices: HashMap::new(),
        by_epc: HashMap::new(),
    };
    let mut presses = Presses::new(state, lease);
    let mut feed = state.feed.subscribe();
    let mut renew = tokio::time::interval(RENEW_EVERY);
    let mut availability = tokio::time::interval(AVAILABILITY_EVERY);
    let mut reannounce: Option<Instant> = None;
    let status_topic = format!("{}/status", config.prefix);
    let ended = loop {
        tokio::select! {
            Some(event) = link.recv() => match event {
                Link::Connected => {
                    state.home_assistant.set(Status::Connected);
                    bridge.connected = true;
                    bridge.on_connect(&status_topic).await;
                }
                Link::Lost { why } => {
                    state.home_assistant.trouble(why);
                    bridge.connected = false;
                }
                Link::Message { topic, payload } if topic == status_topic => {
                    if payload.as_ref() == discovery::ONLINE.as_bytes() {
                        let wait = REANNOUNCE_WITHIN.mul_f64(rand::random_range(0.2..1.0));
                        reannounce = Some(Instant::now() + wait);
                    }
                }
                Link::Message { topic, payload } => {
                    let devices = bridge.devices.iter().map(|(id, a)| (id.as_str(), &a.device));
                    presses.handle(&topic, &payload, devices).await;
                }
            },
            change = feed.recv() => match change {
                Ok(change) => bridge.follow(&change).await,
                // Missed some: saying everything again is always right.
                Err(RecvError::Lagged(_)) => bridge.announce_all().await,
                Err(RecvError::Closed) => break Ended::Shutdown,
            },
            _ = renew.tick() => match lease.take(&state.db, state.clock.now()).await {
                Ok(true) => {}
                Ok(false) => break Ended::LeaseLost,
                Err(error) => tracing::warn!(%error, "cannot renew the Home Assistant bridge's lease"),
            },
            _ = availability.tick() => bridge.refresh_availability().await,
            () = wait_until(reannounce) => {
                reannounce = None;
                bridge.announce_all().await;
            }
            () = state.feed.closed() => break Ended::Shutdown,
        }
    };
    if ended == Ended::Shutdown {
        // Said before leaving, as the last will would: nothing here can be done any more.
        bridge.publish(discovery::BRIDGE_AVAILABILITY, discovery::OFFLINE.into()).await;
    }
    // A clean goodbye: the broker keeps the last will to itself.
    let _ = tokio::time::timeout(PUBLISH_WAIT, bridge.client.disconnect()).await;
    let _ = tokio::time::timeout(PUBLISH_WAIT, connection).await;
    state.home_assistant.set(Status::Standby);
    ended
}

#[allow(clippy::disallowed_methods, reason = "the bridge's own timer")]
async fn wait_until(at: Option<Instant>) {
    match at {
        Some(at) => tokio::time::sleep_until(at).await,
        None => std::future::pending().await,
    }
}

impl Bridge<'_> {
    /// Subscribes, says the bridge is online, and announces everything: a broker that
    /// restarted may have lost what it retained.
    async fn on_connect(&mut self, status_topic: &str) {
        for filter in [status_topic, discovery::PRESS_FILTER] {
            // At most once: a press is never delivered twice.
            if let Err(error) = self.client.subscribe(filter, QoS::AtMostOnce).await {
                tracing::warn!(%error, filter, "cannot subscribe on the MQTT broker");
            }
        }
        self.publish(discovery::BRIDGE_AVAILABILITY, discovery::ONLINE.into()).await;
        self.announce_all().await;
    }

    /// Publishes a retained message; a broker gone for now is no error (everything is said
    /// again on reconnecting).
    async fn publish(&mut self, topic: &str, payload: Vec<u8>) {
        if !self.connected {
            return;
        }
        let sent = self.client.publish(topic, QoS::AtLeastOnce, true, payload);
        if !matches!(tokio::time::timeout(PUBLISH_WAIT, sent).await, Ok(Ok(()))) {
            self.connected = false;
        }
    }

    async fn publish_json(&mut self, topic: &str, payload: &impl serde::Serialize) {
        match serde_json::to_vec(payload) {
            Ok(bytes) => self.publish(topic, bytes).await,
            Err(error) => tracing::warn!(%error, topic, "cannot write a discovery payload"),
        }
    }

    /// Every tag: active ones announced, archived ones removed (they may be retained from
    /// before the bridge last ran).
    async fn announce_all(&mut self) {
        if !self.connected {
            return;
        }
        let all = match tags::all(self.state.db.reader()).await {
            Ok(all) => all,
            Err(error) => return tracing::warn!(%error, "cannot read the tags to announce"),
        };
        for tag in &all {
            self.announce(tag).await;
        }
        tracing::debug!(tags = all.len(), "announced every tag to Home Assistant");
    }

    /// Follows one change of the registry.
    async fn follow(&mut self, change: &Arc<Change>) {
        let epc = |key: &str| change.data.get(key).and_then(Value::as_str).map(Epc::parse);
        match change.kind {
            EventKind::TagChanged | EventKind::TagArchived => {
                if let Some(Ok(epc)) = epc("epc") {
                    self.reread(&epc).await;
                }
            }
            EventKind::TagRetagged => {
                if let Some(Ok(old)) = epc("epc") {
                    self.by_epc.remove(old.as_hex());
                }
                if let Some(Ok(new)) = epc("new_epc") {
                    self.reread(&new).await;
                }
            }
            EventKind::TrialRecorded | EventKind::TrialUpdated => {
                if let Some(id) = epc("epc").and_then(Result::ok).and_then(|e| self.id_of(&e)) {
                    self.publish_state(&id).await;
                }
            }
            EventKind::TaskChanged => {
                if let Some(id) = epc("epc").and_then(Result::ok).and_then(|e| self.id_of(&e)) {
                    self.publish_task(&id).await;
                }
            }
            EventKind::RobotChanged => self.refresh_availability().await,
            _ => {}
        }
    }

    fn id_of(&self, epc: &Epc) -> Option<String> {
        self.by_epc.get(epc.as_hex()).cloned()
    }

    async fn reread(&mut self, epc: &Epc) {
        match tags::get(self.state.db.reader(), epc).await {
            Ok(Some(tag)) => self.announce(&tag).await,
            Ok(None) => {}
            Err(error) => tracing::warn!(%error, %epc, "cannot read a changed tag"),
        }
    }

    /// Says what Home Assistant should show of one tag, or removes it when archived.
    async fn announce(&mut self, tag: &StoredTag) {
        let origin = async {
            let mut conn = self.state.db.reader().acquire().await?;
            retired::origin(&mut conn, &tag.epc).await
        };
        let origin = match origin.await {
            Ok(origin) => origin,
            Err(error) => {
                return tracing::warn!(%error, epc = %tag.epc, "cannot read a tag's history");
            }
        };
        let device = TagDevice::of(&origin, &tag.epc, &tag.entry);
        let before = self.devices.remove(&device.id).map(|announced| announced.device);
        if tag.archived {
            self.by_epc.remove(tag.epc.as_hex());
            return self.remove(before.as_ref().unwrap_or(&device)).await;
        }
        if let Some(before) = &before {
            self.remove_gone_entities(before, &device).await;
        }
        let prefix = self.config.prefix.clone();
        let topics = Topics { prefix: &prefix, device: &device.id };
        for (action, title) in &device.actions {
            let config = ButtonConfig::new(&topics, action, title.clone(), device.device());
            self.publish_json(&topics.button_config(action), &config).await;
        }
        if let Some(two_state) = device.two_state {
            let config = StateConfig::new(&topics, two_state.device_class(), device.device());
            self.publish_json(&topics.state_config(), &config).await;
        }
        self.publish_json(&topics.task_config(), &TaskConfig::new(&topics, device.device())).await;
        let id = device.id.clone();
        self.by_epc.insert(tag.epc.as_hex().to_owned(), id.clone());
        self.devices.insert(id.clone(), Announced { device, available: None });
        match self.online_robots().await {
            Ok(online) => self.publish_availability(&id, &online).await,
            Err(error) => tracing::warn!(%error, "cannot list the robots"),
        }
        self.publish_state(&id).await;
        self.publish_task(&id).await;
    }

    /// Empties the retained configs of entities an edit took away (an action renamed).
    async fn remove_gone_entities(&mut self, before: &TagDevice, now: &TagDevice) {
        let prefix = self.config.prefix.clone();
        let topics = Topics { prefix: &prefix, device: &before.id };
        for (action, _) in &before.actions {
            if !now.actions.iter().any(|(kept, _)| kept == action) {
                self.publish(&topics.button_config(action), Vec::new()).await;
            }
        }
        if before.two_state.is_some() && now.two_state.is_none() {
            self.publish(&topics.state_config(), Vec::new()).await;
            self.publish(&topics.state(), Vec::new()).await;
        }
    }

    /// Removes a device from Home Assistant: empty retained configs, its topics cleared.
    async fn remove(&mut self, device: &TagDevice) {
        let prefix = self.config.prefix.clone();
        let topics = Topics { prefix: &prefix, device: &device.id };
        let mut gone: Vec<String> =
            device.actions.iter().map(|(action, _)| topics.button_config(action)).collect();
        gone.extend([
            topics.state_config(),
            topics.task_config(),
            topics.availability(),
            topics.state(),
            topics.task(),
            topics.task_attributes(),
        ]);
        for topic in gone {
            self.publish(&topic, Vec::new()).await;
        }
    }

    /// The state the newest telling trial gives; nothing (unknown) until one tells.
    async fn publish_state(&mut self, id: &str) {
        let Some(announced) = self.devices.get(id) else { return };
        let Some(two_state) = announced.device.two_state else { return };
        let epc = announced.device.epc.clone();
        let trials =
            match home_assistant::newest_trials(self.state.db.reader(), &epc, TRIALS_FOR_STATE)
                .await
            {
                Ok(trials) => trials,
                Err(error) => return tracing::warn!(%error, %epc, "cannot read a tag's trials"),
            };
        if let Some(on) = two_state.told_by(&trials) {
            let topic = Topics { prefix: &self.config.prefix, device: id }.state();
            self.publish(&topic, if on { "ON" } else { "OFF" }.into()).await;
        }
    }

    /// The tag's newest task in words.
    async fn publish_task(&mut self, id: &str) {
        let Some(announced) = self.devices.get(id) else { return };
        let filter = TaskFilter { epc: Some(announced.device.epc.clone()), ..Default::default() };
        let newest = match tasks::list(self.state.db.reader(), &filter, 0, 1).await {
            Ok(mut newest) => newest.pop(),
            Err(error) => return tracing::warn!(%error, "cannot read a tag's tasks"),
        };
        let topics = Topics { prefix: &self.config.prefix, device: id };
        let (task, attributes) = (topics.task(), topics.task_attributes());
        match newest {
            Some(row) => {
                self.publish_json(&attributes, &task_words::attributes(&row)).await;
                self.publish(&task, task_words::words(&row).into_bytes()).await;
            }
            None => self.publish(&task, b"no task yet".to_vec()).await,
        }
    }

    /// Publishes every device's availability that changed.
    async fn refresh_availability(&mut self) {
        let online = match self.online_robots().await {
            Ok(online) => online,
            Err(error) => return tracing::warn!(%error, "cannot list the robots"),
        };
        let ids: Vec<String> = self.devices.keys().cloned().collect();
        for id in ids {
            self.publish_availability(&id, &online).await;
        }
    }

    /// Available iff an online robot can do at least one of the device's actions.
    async fn publish_availability(&mut self, id: &str, online: &[RobotId]) {
        let Some(announced) = self.devices.get(id) else { return };
        let mut available = false;
        'robots: for robot in online {
            for (action, _) in &announced.device.actions {
                match availability::why_not(self.state, &announced.device.epc, action, robot).await
                {
                    Ok(None) => {
                        available = true;
                        break 'robots;
                    }
                    Ok(Some(_)) => {}
                    Err(error) => return tracing::warn!(%error, "cannot tell what a robot can do"),
                }
            }
        }
        if announced.available == Some(available) {
            return;
        }
        let topic = Topics { prefix: &self.config.prefix, device: id }.availability();
        let word = if available { discovery::ONLINE } else { discovery::OFFLINE };
        self.publish(&topic, word.into()).await;
        if self.connected
            && let Some(announced) = self.devices.get_mut(id)
        {
            announced.available = Some(available);
        }
    }

    async fn online_robots(&self) -> sqlx::Result<Vec<RobotId>> {
        let known = robots::list(self.state.db.reader(), None, 10_000).await?;
        let now = self.state.clock.now();
        Ok(known
            .into_iter()
            .map(|robot| robot.id)
            .filter(|id| self.state.presence.online(id.as_str(), now))
            .collect())
    }
}
