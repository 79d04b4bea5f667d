//! Home Assistant's MQTT discovery: the topics and the config payloads of the entities the
//! bridge announces, only the fields it uses. A tag is one device; its entities are one button
//! per action, a binary sensor for a two-state tag, and a sensor for its newest task.

use serde::Serialize;

/// Where this registry's own topics live, beside the discovery prefix.
pub const BASE: &str = "pps";
/// The bridge's own availability: its last will sets it `offline`, which every entity lists.
pub const BRIDGE_AVAILABILITY: &str = "pps/bridge/availability";
pub const ONLINE: &str = "online";
pub const OFFLINE: &str = "offline";
/// What a button sends when pressed.
pub const PRESS: &str = "PRESS";

/// The topics of one device, keyed by its id (which survives a retag).
#[derive(Debug, Clone)]
pub struct Topics<'a> {
    pub prefix: &'a str,
    pub device: &'a str,
}

impl Topics<'_> {
    pub fn button_config(&self, action: &str) -> String {
        format!("{}/button/{}/{action}/config", self.prefix, self.device)
    }

    pub fn state_config(&self) -> String {
        format!("{}/binary_sensor/{}/state/config", self.prefix, self.device)
    }

    pub fn task_config(&self) -> String {
        format!("{}/sensor/{}/task/config", self.prefix, self.device)
    }

    pub fn press(&self, action: &str) -> String {
        format!("{BASE}/{}/press/{action}", self.device)
    }

    pub fn availability(&self) -> String {
        format!("{BASE}/{}/availability", self.device)
    }

    pub fn state(&self) -> String {
        format!("{BASE}/{}/state", self.device)
    }

    pub fn task(&self) -> String {
        format!("{BASE}/{}/task", self.device)
    }

    pub fn task_attributes(&self) -> String {
        format!("{BASE}/{}/task/attributes", self.device)
    }
}

/// The press topics to subscribe to: `pps/<device>/press/<action>`.
pub const PRESS_FILTER: &str = "pps/+/press/+";

/// The device and action a press topic names.
pub fn parse_press_topic(topic: &str) -> Option<(&str, &str)> {
    let rest = topic.strip_prefix(BASE)?.strip_prefix('/')?;
    let (device, action) = rest.split_once("/press/")?;
    (!device.is_empty() && !action.is_empty() && !action.contains('/')).then_some((device, action))
}

/// The device block every entity of a tag repeats (Home Assistant merges them).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Device {
    /// The device id first (stable across a retag), then the tag's EPC now.
    pub identifiers: Vec<String>,
    pub name: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub suggested_area: Option<String>,
    pub manufacturer: &'static str,
    /// The tag's kind in words ("Light switch (toggle)").
    pub model: String,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Availability {
    pub topic: String,
}

/// The two availability topics every entity lists: the bridge's and its device's.
fn availability(topics: &Topics<'_>) -> Vec<Availability> {
    vec![
        Availability { topic: BRIDGE_AVAILABILITY.into() },
        Availability { topic: topics.availability() },
    ]
}

/// A button: one action of the tag.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ButtonConfig {
    pub name: String,
    pub unique_id: String,
    pub command_topic: String,
    pub payload_press: &'static str,
    /// At most once: a press redelivered after a reconnect must not become a second task.
    pub qos: u8,
    pub retain: bool,
    pub availability: Vec<Availability>,
    pub availability_mode: &'static str,
    pub icon: &'static str,
    pub device: Device,
}

/// The tag's state as its success detector last saw it (`ON` light or open drawer).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StateConfig {
    /// None: the entity is named as its device ("hallway light switch").
    pub name: Option<String>,
    pub unique_id: String,
    pub state_topic: String,
    pub device_class: &'static str,
    pub payload_on: &'static str,
    pub payload_off: &'static str,
    pub availability: Vec<Availability>,
    pub availability_mode: &'static str,
    pub device: Device,
}

/// The tag's newest task in words, its fields as attributes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TaskConfig {
    pub name: &'static str,
    pub unique_id: String,
    pub state_topic: String,
    pub json_attributes_topic: String,
    pub icon: &'static str,
    pub availability: Vec<Availability>,
    pub availability_mode: &'static str,
    pub device: Device,
}

impl ButtonConfig {
    pub fn new(topics: &Topics<'_>, action: &str, title: String, device: Device) -> Self {
        Self {
            name: title,
            unique_id: format!("{}_{action}", topics.device),
            command_topic: topics.press(action),
            payload_press: PRESS,
            qos: 0,
            retain: false,
            availability: availability(topics),
            availability_mode: "all",
            icon: "mdi:robot-industrial",
            device,
        }
    }
}

impl StateConfig {
    pub fn new(topics: &Topics<'_>, device_class: &'static str, device: Device) -> Self {
        Self {
            name: None,
            unique_id: format!("{}_state", topics.device),
            state_topic: topics.state(),
            device_class,
            payload_on: "ON",
            payload_off: "OFF",
            availability: availability(topics),
            availability_mode: "all",
            device,
        }
    }
}

impl TaskConfig {
    pub fn new(topics: &Topics<'_>, device: Device) -> Self {
        Self {
            name: "Robot task",
            unique_id: format!("{}_task", topics.device),
            state_topic: topics.task(),
            json_attributes_topic: topics.task_attributes(),
            icon: "mdi:robot",
            // The task's words stay readable while no robot is online: they say why.
            availability: vec![Availability { topic: BRIDGE_AVAILABILITY.into() }],
            availability_mode: "all",
            device,
        }
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    #[test]
    fn press_topics_name_their_device_and_action() {
        let topics = Topics { prefix: "homeassistant", device: "pps_355ab1c60000001000000001" };
        let press = topics.press("off");
        assert_eq!(press, "pps/pps_355ab1c60000001000000001/press/off");
        assert_eq!(parse_press_topic(&press), Some(("pps_355ab1c60000001000000001", "off")));
        for wrong in ["pps/x/press/", "pps//press/on", "other/x/press/on", "pps/x/press/on/more"] {
            assert_eq!(parse_press_topic(wrong), None, "{wrong}");
        }
    }

    #[test]
    fn a_button_config_is_what_home_assistant_reads() {
        let topics = Topics { prefix: "homeassistant", device: "pps_1001" };
        let device = Device {
            identifiers: vec!["pps_1001".into(), "1001".into()],
            name: "hallway switch".into(),
            suggested_area: Some("hallway".into()),
            manufacturer: "PPS-tag registry",
            model: "Light switch (toggle)".into(),
        };
        let config = ButtonConfig::new(&topics, "off", "Turn off".into(), device);
        assert_eq!(topics.button_config("off"), "homeassistant/button/pps_1001/off/config");
        let json = serde_json::to_value(&config).unwrap();
        assert_eq!(json["name"], "Turn off");
        assert_eq!(json["unique_id"], "pps_1001_off");
        assert_eq!(json["command_topic"], "pps/pps_1001/press/off");
        assert_eq!(json["payload_press"], "PRESS");
        assert_eq!(json["device"]["suggested_area"], "hallway");
        assert_eq!(
            json["availability"],
            json!([{"topic": "pps/bridge/availability"}, {"topic": "pps/pps_1001/availability"}])
        );
    }
}
