//! The seed entries are what an empty registry starts with: each must be a valid, PUT-able
//! entry of the paper's devices, readable by the robots.

use std::path::PathBuf;

use pps_schema::{
    BehaviorKind, BehaviorParams, Epc, READ_ONLY_TAG_FIELDS, SwitchMotion, TagEntry,
    schema_document, validate_tag,
};
use serde_json::Value;

fn seed_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../seed_tags")
}

fn seed(file: &str) -> Value {
    let path = seed_dir().join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn seeds() -> Vec<(String, Value)> {
    let mut files: Vec<String> = std::fs::read_dir(seed_dir())
        .unwrap()
        .map(|entry| entry.unwrap().file_name().into_string().unwrap())
        .filter(|name| name.ends_with(".json"))
        .collect();
    files.sort();
    files.into_iter().map(|f| (f.clone(), seed(&f))).collect()
}

/// JSON equality that treats `5` and `5.0` as the same number.
fn same_json(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.as_f64() == y.as_f64(),
        (Value::Array(x), Value::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(x, y)| same_json(x, y))
        }
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| same_json(v, w)))
        }
        _ => a == b,
    }
}

#[test]
fn there_is_one_seed_per_device_of_the_paper_with_its_fixed_epc() {
    let expected = [
        ("ada_light_switch.json", "355AB1C60000002000000001", "ada light switch"),
        ("drawer.json", "355AB1C60000004000000001", "drawer"),
        ("lamp.json", "355AB1C60000003000000001", "lamp"),
        ("light_switch.json", "355AB1C60000001000000001", "light switch"),
        ("trash_can.json", "355AB1C60000005000000001", "trash can"),
    ];
    let seeds = seeds();
    assert_eq!(seeds.len(), expected.len());
    for ((file, entry), (want_file, epc, kind)) in seeds.iter().zip(expected) {
        assert_eq!(file, want_file);
        assert_eq!(entry["epc"], epc, "{file}");
        assert_eq!(Epc::parse(epc).unwrap().as_hex(), epc, "{file}: canonical");
        assert_eq!(entry["properties"]["type"], kind, "{file}");
    }
}

#[test]
fn every_seed_validates_and_is_put_able() {
    for (file, entry) in seeds() {
        if let Err(errors) = validate_tag(&entry) {
            panic!("{file}: {errors}");
        }
        for field in READ_ONLY_TAG_FIELDS {
            assert!(entry.get(field).is_none(), "{file} holds read-only {field}");
        }
        assert!(entry["properties"]["location"]["room"].is_string(), "{file}: room");
    }
}

#[test]
fn every_seed_round_trips_through_the_types() {
    for (file, json) in seeds() {
        let entry: TagEntry =
            serde_json::from_value(json.clone()).unwrap_or_else(|e| panic!("{file}: {e}"));
        let back = serde_json::to_value(&entry).unwrap();
        assert!(same_json(&back, &json), "{file}:\n{back:#}\n!=\n{json:#}");
    }
}

#[test]
fn seeds_use_the_paper_action_names_and_behaviours() {
    let behaviour = |file: &str, action: &str| {
        let entry: TagEntry = serde_json::from_value(seed(file)).unwrap();
        let (_, spec) =
            entry.behavior_for(action).unwrap_or_else(|| panic!("{file}: no action {action}"));
        spec.params.clone()
    };
    for (file, action, kind) in [
        ("light_switch.json", "on", BehaviorKind::LightSwitch),
        ("light_switch.json", "off", BehaviorKind::LightSwitch),
        ("ada_light_switch.json", "on", BehaviorKind::LightSwitch),
        ("ada_light_switch.json", "off", BehaviorKind::LightSwitch),
        ("lamp.json", "on", BehaviorKind::PullLamp),
        ("lamp.json", "off", BehaviorKind::PullLamp),
        ("drawer.json", "open", BehaviorKind::PullBack),
        ("drawer.json", "close", BehaviorKind::Push),
        ("trash_can.json", "drop", BehaviorKind::Drop),
    ] {
        assert_eq!(behaviour(file, action).kind(), kind, "{file} {action}");
    }

    // The flip-type switch sweeps; the ADA rocker is pressed above and below its centre.
    let BehaviorParams::LightSwitch(flip_on) = behaviour("light_switch.json", "on") else {
        unreachable!()
    };
    assert_eq!(flip_on.motion, SwitchMotion::Flip);
    assert_eq!(
        (
            flip_on.max_carriage_force,
            flip_on.max_travel,
            flip_on.contact_force,
            flip_on.wall_clearance
        ),
        (12.0, 0.15, 2.0, 0.02)
    );
    let BehaviorParams::LightSwitch(ada_on) = behaviour("ada_light_switch.json", "on") else {
        unreachable!()
    };
    let BehaviorParams::LightSwitch(ada_off) = behaviour("ada_light_switch.json", "off") else {
        unreachable!()
    };
    assert_eq!(ada_on.motion, SwitchMotion::Press);
    assert_eq!((ada_on.force_threshold, ada_on.height_offset), (3.0, 0.02));
    assert_eq!((ada_off.force_threshold, ada_off.height_offset), (3.0, -0.02));

    let BehaviorParams::PullLamp(lamp) = behaviour("lamp.json", "on") else { unreachable!() };
    assert_eq!(
        (lamp.alignment_backoff, lamp.max_pull_force, lamp.max_pull_distance),
        (0.08, 10.0, 0.07)
    );
    let BehaviorParams::PullBack(pull) = behaviour("drawer.json", "open") else { unreachable!() };
    assert_eq!((pull.grasp_force, pull.step, pull.success_ratio), (2.0, 0.2, 0.5));
    let BehaviorParams::Drop(drop) = behaviour("trash_can.json", "drop") else { unreachable!() };
    assert_eq!(drop.standoff, 0.45);
}

#[test]
fn the_ada_switch_is_the_papers_fig_4_entry() {
    let entry: TagEntry = serde_json::from_value(seed("ada_light_switch.json")).unwrap();
    let p = &entry.properties;
    assert_eq!(p.name, "A D A light switch 1");
    assert_eq!((p.height, p.switch_travel, p.on_plane), (Some(1.22), Some(0.02), Some(true)));
    for key in ["push_top", "push_bottom"] {
        let spec = &entry.behaviors[key];
        let BehaviorParams::LightSwitch(el_e) = spec.params_for(Some("el-e"), "el-e-1").unwrap()
        else {
            unreachable!()
        };
        assert_eq!(el_e.gripper_deg, 5.0, "{key}");
    }
}

/// Robots read the paper's numbers from the registry, not from constants in their code, so
/// the seeds state every parameter that has a default.
#[test]
fn seeds_state_every_parameter() {
    for (file, entry) in seeds() {
        for (key, spec) in entry["behaviors"].as_object().unwrap() {
            let name = spec["behavior"].as_str().unwrap();
            let schema = schema_document(name).unwrap();
            for (param, definition) in schema["$defs"]["params"]["properties"].as_object().unwrap()
            {
                if definition.get("default").is_some() {
                    assert!(spec.get(param).is_some(), "{file}: {key} leaves out {param}");
                }
            }
        }
    }
}

#[test]
fn several_seeds_carry_el_e_overrides() {
    let with_overrides = seeds()
        .into_iter()
        .filter(|(_, entry)| {
            entry["properties"]["robots"]["el-e"].is_object()
                || entry["behaviors"]
                    .as_object()
                    .unwrap()
                    .values()
                    .any(|b| b["robots"]["el-e"].is_object())
        })
        .count();
    assert!(with_overrides >= 3, "{with_overrides}");
}
