//! What Home Assistant shows of one tag: its device and entities, read off the tag's entry.

use pps_schema::Epc;
use serde_json::Value;

use super::discovery::Device;
use super::two_state::TwoState;

/// One tag as a Home Assistant device.
#[derive(Debug, Clone, PartialEq)]
pub struct TagDevice {
    /// `pps_` and the first EPC the tag had, lower-case: the same after a retag.
    pub id: String,
    pub epc: Epc,
    pub name: String,
    pub room: Option<String>,
    /// The tag's kind in words.
    pub model: String,
    /// Each action and its title ("off", "Turn off"), in the entry's order.
    pub actions: Vec<(String, String)>,
    pub two_state: Option<TwoState>,
}

impl TagDevice {
    /// The device of the tag `entry` whose first EPC was `origin`.
    pub fn of(origin: &Epc, epc: &Epc, entry: &Value) -> Self {
        let properties = &entry["properties"];
        let text = |value: &Value| value.as_str().map(str::to_owned).filter(|t| !t.is_empty());
        let kind = text(&properties["type"]);
        let actions: Vec<(String, String)> = entry["actions"]
            .as_object()
            .map(|actions| {
                actions.keys().map(|action| (action.clone(), action_title(action))).collect()
            })
            .unwrap_or_default();
        Self {
            id: device_id(origin),
            epc: epc.clone(),
            name: text(&properties["name"])
                .or_else(|| kind.clone())
                .unwrap_or_else(|| epc.as_hex().to_owned()),
            room: text(&properties["location"]["room"]),
            model: kind.as_deref().map_or_else(|| "PPS-tagged device".to_owned(), kind_title),
            two_state: TwoState::of(actions.iter().map(|(action, _)| action.as_str())),
            actions,
        }
    }

    /// The device block of every entity.
    pub fn device(&self) -> Device {
        Device {
            identifiers: vec![self.id.clone(), self.epc.as_hex().to_owned()],
            name: self.name.clone(),
            suggested_area: self.room.clone(),
            manufacturer: "PPS-tag registry",
            model: self.model.clone(),
        }
    }
}

/// The device id of the tag whose first EPC was `origin`.
pub fn device_id(origin: &Epc) -> String {
    format!("pps_{}", origin.as_hex().to_ascii_lowercase())
}

/// An action's title as the schemas give it ("Turn off"), as the web UI shows it.
fn action_title(action: &str) -> String {
    titled(&["properties", "actions"], action)
}

/// A kind's title as the schemas give it ("Light switch (toggle)").
fn kind_title(kind: &str) -> String {
    titled(&["$defs", "properties", "properties", "type"], kind)
}

/// The title the tag schema gives `value` at `path` (its `x-titles` or its choices), else the
/// value in words: the rule of the web UI's `titleOf`.
fn titled(path: &[&str], value: &str) -> String {
    let schema = pps_schema::schema_document("tag")
        .and_then(|tag| path.iter().try_fold(tag, |at, key| at.get(*key)));
    let known = schema.and_then(|prop| {
        prop["x-titles"][value].as_str().or_else(|| {
            prop["oneOf"].as_array()?.iter().find_map(|choice| {
                (choice["const"] == value).then(|| choice["title"].as_str()).flatten()
            })
        })
    });
    known.map_or_else(|| sentence(&value.replace('_', " ")), str::to_owned)
}

fn sentence(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map_or_else(String::new, |first| first.to_uppercase().chain(chars).collect())
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    fn epc(hex: &str) -> Epc {
        Epc::parse(hex).unwrap()
    }

    #[test]
    fn a_seeded_switch_is_a_device_in_its_room_with_titled_buttons() {
        let entry: Value =
            serde_json::from_str(include_str!("../../../seed_tags/light_switch.json")).unwrap();
        let now = epc(entry["epc"].as_str().unwrap());
        let first = epc("E20034120000000000001001");
        let device = TagDevice::of(&first, &now, &entry);
        assert_eq!(device.id, "pps_e20034120000000000001001");
        assert_eq!(device.room.as_deref(), Some("living room"));
        assert_eq!(device.model, "Light switch (toggle)");
        let titles: Vec<&str> = device.actions.iter().map(|(_, title)| title.as_str()).collect();
        assert!(titles.contains(&"Turn off") && titles.contains(&"Turn on"), "{titles:?}");
        assert_eq!(device.two_state, Some(TwoState::Light));
        let block = device.device();
        assert_eq!(block.identifiers, vec![device.id.clone(), now.as_hex().to_owned()]);
    }

    #[test]
    fn unknown_actions_and_kinds_read_as_words() {
        let entry = json!({
            "properties": { "type": "window crank" },
            "actions": { "crank_open": "crank" }
        });
        let id = epc("1234");
        let device = TagDevice::of(&id, &id, &entry);
        assert_eq!(device.name, "window crank", "no name: the kind names it");
        assert_eq!(device.model, "Window crank");
        assert_eq!(device.actions, vec![("crank_open".to_owned(), "Crank open".to_owned())]);
        assert_eq!(device.room, None);
        assert_eq!(device.two_state, None);
    }
}
