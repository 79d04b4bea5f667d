//! The effective entry: one tag as one robot should use it (DESIGN §3).
//!
//! Merge order, later wins: the stored entry (`base`) ← values learned from the robot class's
//! trials (`learned`) ← the class override (`class:<class>`) ← the robot's own override
//! (`robot:<id>`). Overrides live in the `robots` maps of `properties` and of each behaviour;
//! the merged entry has them applied and removed, and every merged leaf carries its source.
//! Pure functions: no database, no I/O.

use std::collections::BTreeMap;

use pps_schema::pointer::{escape, unescape};
use pps_schema::{
    BehaviorKind, BehaviorSpec, HOUSEHOLD_COLOR, LEARNED_COLOR, LearnedColor, TagSize,
};
use serde_json::{Map, Value, json};

use crate::answers::effective::{EffectiveEntry, UnavailableAction};
use crate::store::learning::Learned;
use crate::store::robots::StoredRobot;

/// What the confirmed reads taught of the tag itself: the colour models learned from the robot
/// class's (the tag's own and its household's) and the size learned from every robot's.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LearnedLooks {
    pub tag: Option<LearnedColor>,
    pub household: Option<LearnedColor>,
    pub size: Option<TagSize>,
}

/// Merges `entry` for `robot` (which may be unregistered) and checks what it can run.
pub fn merge(
    epc: &str,
    revision: i64,
    entry: &Value,
    robot_id: &str,
    robot: Option<&StoredRobot>,
    learned: &[Learned],
    looks: &LearnedLooks,
) -> EffectiveEntry {
    let class = robot.and_then(|r| r.class.as_deref());
    let mut provenance = BTreeMap::new();
    let mut merged = entry.clone();

    let layers: Vec<(String, Option<&str>)> = {
        let mut layers = Vec::new();
        if let Some(class) = class {
            layers.push((format!("class:{class}"), Some(class)));
        }
        layers.push((format!("robot:{robot_id}"), Some(robot_id)));
        layers
    };

    if let Some(properties) = merged.get_mut("properties").and_then(Value::as_object_mut) {
        let overrides = properties.remove("robots");
        record_leaves("/properties", &Value::Object(properties.clone()), "base", &mut provenance);
        // Only where the entry has none: a size a caretaker measured stands.
        if let Some(size) = looks.size
            && !properties.contains_key("tag_size")
        {
            let value = json!(size);
            record_leaves("/properties/tag_size", &value, "learned", &mut provenance);
            properties.insert("tag_size".to_owned(), value);
        }
        for (source, key) in &layers {
            if let Some(layer) = key.and_then(|k| overrides.as_ref()?.get(k)) {
                apply(properties, layer, "/properties", source, &mut provenance);
            }
        }
    }
    if let Some(properties) = merged.get_mut("properties").and_then(Value::as_object_mut) {
        // Beside the entry's own `color_segmentation`, never over it: the robot chooses.
        for (key, model) in [(LEARNED_COLOR, looks.tag), (HOUSEHOLD_COLOR, looks.household)] {
            if let Some(model) = model {
                let value = json!(model);
                record_leaves(&format!("/properties/{key}"), &value, "learned", &mut provenance);
                properties.insert(key.to_owned(), value);
            }
        }
    }
    if let Some(behaviors) = merged.get_mut("behaviors").and_then(Value::as_object_mut) {
        for (name, behavior) in behaviors.iter_mut() {
            let Some(behavior) = behavior.as_object_mut() else { continue };
            let overrides = behavior.remove("robots");
            let base = format!("/behaviors/{}", escape(name));
            record_leaves(&base, &Value::Object(behavior.clone()), "base", &mut provenance);
            for learned in learned.iter().filter(|l| l.pointer.starts_with(&format!("{base}/"))) {
                let field = &learned.pointer[base.len() + 1..];
                behavior.insert(unescape(field), json!(learned.value));
                provenance.insert(learned.pointer.clone(), "learned".to_owned());
            }
            for (source, key) in &layers {
                if let Some(layer) = key.and_then(|k| overrides.as_ref()?.get(k)) {
                    apply(behavior, layer, &base, source, &mut provenance);
                }
            }
        }
    }

    let unavailable = unavailable_actions(&merged, robot_id, robot);
    EffectiveEntry {
        epc: epc.to_owned(),
        robot: robot_id.to_owned(),
        revision,
        entry: merged,
        provenance,
        unavailable_actions: unavailable,
    }
}

/// Overlays `layer` onto `target` (objects merge, anything else replaces), recording sources.
fn apply(
    target: &mut Map<String, Value>,
    layer: &Value,
    at: &str,
    source: &str,
    provenance: &mut BTreeMap<String, String>,
) {
    let Some(layer) = layer.as_object() else { return };
    for (key, value) in layer {
        let pointer = format!("{at}/{}", escape(key));
        match (target.get_mut(key), value) {
            (Some(Value::Object(existing)), Value::Object(_)) => {
                apply(existing, value, &pointer, source, provenance)
            }
            _ => {
                provenance.retain(|p, _| !(p == &pointer || p.starts_with(&format!("{pointer}/"))));
                record_leaves(&pointer, value, source, provenance);
                target.insert(key.clone(), value.clone());
            }
        }
    }
}

/// Records every leaf under `value` (objects are walked; arrays and scalars are leaves).
fn record_leaves(at: &str, value: &Value, source: &str, provenance: &mut BTreeMap<String, String>) {
    match value {
        Value::Object(object) if !object.is_empty() => {
            for (key, child) in object {
                record_leaves(&format!("{at}/{}", escape(key)), child, source, provenance);
            }
        }
        _ => {
            provenance.insert(at.to_owned(), source.to_owned());
        }
    }
}

/// Actions the robot cannot run, each with the reason.
fn unavailable_actions(
    merged: &Value,
    robot_id: &str,
    robot: Option<&StoredRobot>,
) -> Vec<UnavailableAction> {
    let Some(actions) = merged.get("actions").and_then(Value::as_object) else { return Vec::new() };
    let document = robot.and_then(|r| r.document.as_ref());
    let mut unavailable = Vec::new();
    for (action, behavior_key) in actions {
        let Some(behavior_key) = behavior_key.as_str() else { continue };
        let spec = merged.get("behaviors").and_then(|b| b.get(behavior_key));
        let reason = match (document, spec) {
            (None, _) => Some(format!(
                "robot {robot_id} is not registered yet, so its capabilities and limits are \
                 unknown; an admin registers it with PUT /api/v1/robots/{robot_id}"
            )),
            (_, None) => Some(format!("behaviour {behavior_key} is missing from the entry")),
            (Some(document), Some(spec)) => reason_unavailable(document, spec, merged, robot_id),
        };
        if let Some(reason) = reason {
            unavailable.push(UnavailableAction {
                action: action.clone(),
                behavior: behavior_key.to_owned(),
                reason,
            });
        }
    }
    unavailable
}

fn reason_unavailable(
    robot: &Value,
    spec: &Value,
    merged: &Value,
    robot_id: &str,
) -> Option<String> {
    let spec: BehaviorSpec = match serde_json::from_value(spec.clone()) {
        Ok(spec) => spec,
        Err(error) => {
            return Some(format!("its parameters do not fit this robot's overrides: {error}"));
        }
    };
    let kind: BehaviorKind = spec.params.kind();
    let capable = robot
        .get("capabilities")
        .and_then(Value::as_array)
        .is_some_and(|caps| caps.iter().any(|c| c.as_str() == Some(kind.as_str())));
    if !capable {
        return Some(format!(
            "robot {robot_id} cannot run the {kind} behaviour (not among its capabilities)"
        ));
    }
    let limits = robot.get("limits");
    let max_force = limits.and_then(|l| l.get("max_force")).and_then(Value::as_f64);
    if let (Some(max_force), Some(needed)) = (max_force, spec.params.peak_force())
        && needed > max_force
    {
        return Some(format!(
            "the {kind} behaviour needs up to {needed} N but robot {robot_id} may apply at most {max_force} N"
        ));
    }
    let max_height = limits.and_then(|l| l.get("max_reach_height")).and_then(Value::as_f64);
    let height = merged.pointer("/properties/height").and_then(Value::as_f64);
    if let (Some(max_height), Some(height)) = (max_height, height)
        && height > max_height
    {
        return Some(format!(
            "the tag is {height} m high but robot {robot_id} reaches at most {max_height} m"
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn robot(class: Option<&str>, capabilities: &[&str], max_force: f64) -> StoredRobot {
        StoredRobot {
            id: pps_schema::RobotId::parse("el-e-1").unwrap(),
            class: class.map(str::to_owned),
            document: Some(json!({ "id": "el-e-1", "class": class, "name": "EL-E",
                "capabilities": capabilities, "limits": { "max_force": max_force } })),
        }
    }

    /// The effective entry as robots read it.
    fn json(effective: EffectiveEntry) -> Value {
        serde_json::to_value(effective).unwrap()
    }

    fn entry() -> Value {
        serde_json::from_str(include_str!("../../../seed_tags/drawer.json")).unwrap()
    }

    #[test]
    fn layers_apply_in_order_with_provenance() {
        let mut entry = entry();
        entry["behaviors"]["pull_open"]["robots"] = json!({
            "el-e": { "grasp_force": 3.0, "step": 0.15 },
            "el-e-1": { "step": 0.1 }
        });
        let learned =
            [Learned { pointer: "/behaviors/pull_open/pull_distance".into(), value: 0.31 }];
        let robot = robot(Some("el-e"), &["pull_back", "push"], 15.0);
        let out =
            json(merge("E", 3, &entry, "el-e-1", Some(&robot), &learned, &LearnedLooks::default()));
        let pull = &out["entry"]["behaviors"]["pull_open"];
        assert_eq!(pull["pull_distance"], 0.31);
        assert_eq!(pull["grasp_force"], 3.0);
        assert_eq!(pull["step"], 0.1);
        assert!(pull.get("robots").is_none(), "overrides are applied, not passed on");
        let provenance = &out["provenance"];
        assert_eq!(provenance["/behaviors/pull_open/pull_distance"], "learned");
        assert_eq!(provenance["/behaviors/pull_open/grasp_force"], "class:el-e");
        assert_eq!(provenance["/behaviors/pull_open/step"], "robot:el-e-1");
        assert_eq!(provenance["/behaviors/pull_open/stop_force"], "base");
        assert_eq!(provenance["/properties/color_segmentation/hue_deg"], "class:el-e");
        assert_eq!(out["unavailable_actions"], json!([]));
        let merged: pps_schema::TagEntry = serde_json::from_value(out["entry"].clone()).unwrap();
        assert_eq!(merged.actions.len(), 2);
    }

    #[test]
    fn a_class_override_beats_learned_values() {
        let mut entry = entry();
        entry["behaviors"]["pull_open"]["robots"] = json!({ "el-e": { "pull_distance": 0.2 } });
        let learned =
            [Learned { pointer: "/behaviors/pull_open/pull_distance".into(), value: 0.31 }];
        let out = json(merge(
            "E",
            1,
            &entry,
            "el-e-1",
            Some(&robot(Some("el-e"), &["pull_back"], 15.0)),
            &learned,
            &LearnedLooks::default(),
        ));
        assert_eq!(out["entry"]["behaviors"]["pull_open"]["pull_distance"], 0.2);
        assert_eq!(out["provenance"]["/behaviors/pull_open/pull_distance"], "class:el-e");
    }

    #[test]
    fn learned_colours_stand_beside_the_entrys_own() {
        let model = |from: f64, trials: u64| LearnedColor {
            segmentation: pps_schema::ColorSegmentation {
                hue_deg: [from, 9.0],
                saturation: [0.7, 1.0],
                value: [0.2, 1.0],
            },
            trials,
        };
        let colours = LearnedLooks {
            tag: Some(model(352.0, 4)),
            household: Some(model(350.0, 9)),
            size: None,
        };
        let robot = robot(Some("el-e"), &["pull_back", "push"], 15.0);
        let out = json(merge("E", 1, &entry(), "el-e-1", Some(&robot), &[], &colours));
        let properties = &out["entry"]["properties"];
        assert_eq!(properties["color_segmentation"]["hue_deg"], json!([340, 20]));
        assert_eq!(properties["learned_color_segmentation"]["hue_deg"], json!([352.0, 9.0]));
        assert_eq!(properties["household_color_segmentation"]["trials"], 9);
        let provenance = &out["provenance"];
        assert_eq!(provenance["/properties/color_segmentation/hue_deg"], "class:el-e");
        assert_eq!(provenance["/properties/learned_color_segmentation/hue_deg"], "learned");
        assert_eq!(provenance["/properties/household_color_segmentation/saturation"], "learned");
        let merged: pps_schema::TagEntry = serde_json::from_value(out["entry"].clone()).unwrap();
        assert_eq!(merged.properties.household_color(), colours.household);
        assert_eq!(merged.properties.learned_color(), colours.tag);
    }

    #[test]
    fn a_learned_size_fills_in_only_where_the_entry_has_none() {
        let looks = LearnedLooks {
            size: Some(TagSize { width: 0.162, height: 0.238 }),
            ..LearnedLooks::default()
        };
        let robot = robot(Some("el-e"), &["pull_back", "push"], 15.0);
        let out = json(merge("E", 1, &entry(), "el-e-1", Some(&robot), &[], &looks));
        assert_eq!(
            out["entry"]["properties"]["tag_size"],
            json!({"width": 0.162, "height": 0.238})
        );
        assert_eq!(out["provenance"]["/properties/tag_size/width"], "learned");
        assert_eq!(out["provenance"]["/properties/tag_size/height"], "learned");

        let mut measured = entry();
        measured["properties"]["tag_size"] = json!({"width": 0.16, "height": 0.24});
        let out = json(merge("E", 1, &measured, "el-e-1", Some(&robot), &[], &looks));
        assert_eq!(out["entry"]["properties"]["tag_size"], json!({"width": 0.16, "height": 0.24}));
        assert_eq!(out["provenance"]["/properties/tag_size/width"], "base");

        // A class's own size beats the learned one, as every override beats what was learned.
        let mut class_size = entry();
        class_size["properties"]["robots"]["el-e"]["tag_size"] =
            json!({"width": 0.1, "height": 0.2});
        let out = json(merge("E", 1, &class_size, "el-e-1", Some(&robot), &[], &looks));
        assert_eq!(out["entry"]["properties"]["tag_size"], json!({"width": 0.1, "height": 0.2}));
        assert_eq!(out["provenance"]["/properties/tag_size/height"], "class:el-e");
    }

    #[test]
    fn missing_capabilities_limits_and_registration_make_actions_unavailable() {
        let weak = robot(Some("tiny"), &["push"], 5.0);
        let out =
            json(merge("E", 1, &entry(), "el-e-1", Some(&weak), &[], &LearnedLooks::default()));
        let reasons: Vec<(String, String)> = out["unavailable_actions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|u| (u["action"].as_str().unwrap().into(), u["reason"].as_str().unwrap().into()))
            .collect();
        assert_eq!(reasons.len(), 2, "{reasons:?}");
        assert_eq!(reasons[0].0, "close");
        assert!(reasons[0].1.contains("at most 5 N"), "{reasons:?}");
        assert_eq!(reasons[1].0, "open");
        assert!(reasons[1].1.contains("pull_back"), "{reasons:?}");

        let unknown = json(merge("E", 1, &entry(), "el-e-9", None, &[], &LearnedLooks::default()));
        assert_eq!(unknown["unavailable_actions"].as_array().unwrap().len(), 2);
        assert!(
            unknown["unavailable_actions"][0]["reason"]
                .as_str()
                .unwrap()
                .contains("not registered")
        );
    }
}
