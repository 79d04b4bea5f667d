//! The serde types and the behaviour schemas must describe the same parameters with the same
//! defaults, or a robot would run with values the caretaker never saw in the schema.

use pps_schema::{BehaviorKind, BehaviorSpec, schema_document, validate_tag};
use serde_json::{Map, Value, json};

fn params(kind: BehaviorKind) -> &'static Map<String, Value> {
    schema_document(kind.schema_name()).unwrap()["$defs"]["params"]["properties"]
        .as_object()
        .unwrap()
}

/// The smallest spec the schema accepts: `behavior` and the required parameters, the latter
/// at their maximum.
fn minimal(kind: BehaviorKind) -> Value {
    let schema = schema_document(kind.schema_name()).unwrap();
    let mut spec = json!({"behavior": kind.as_str()});
    for required in schema["required"].as_array().unwrap() {
        let name = required.as_str().unwrap();
        if name != "behavior" {
            spec[name] = params(kind)[name]["maximum"].clone();
        }
    }
    spec
}

fn in_entry(spec: Value) -> Value {
    json!({
        "epc": "355AB1C60000009000000001",
        "properties": {"name": "test"},
        "actions": {"act": "b"},
        "behaviors": {"b": spec}
    })
}

#[test]
fn serde_defaults_are_the_schema_defaults() {
    for kind in BehaviorKind::ALL {
        let spec = minimal(kind);
        validate_tag(&in_entry(spec.clone())).unwrap_or_else(|e| panic!("{kind}: {e}"));
        let typed: BehaviorSpec = serde_json::from_value(spec.clone()).unwrap();
        assert_eq!(typed.kind(), kind);
        let filled = serde_json::to_value(&typed).unwrap();
        for (name, definition) in params(kind) {
            match (definition.get("default"), filled.get(name)) {
                (Some(default), Some(value)) => {
                    assert_eq!(default.as_f64(), value.as_f64(), "{kind}.{name}");
                    assert_eq!(default.as_str(), value.as_str(), "{kind}.{name}");
                }
                (Some(_), None) => panic!("{kind}.{name}: the type has no default"),
                (None, Some(value)) => {
                    assert_eq!(value.as_f64(), spec[name].as_f64(), "{kind}.{name}")
                }
                (None, None) => {}
            }
        }
    }
}

#[test]
fn the_types_hold_exactly_the_schema_parameters() {
    for kind in BehaviorKind::ALL {
        let mut spec = minimal(kind);
        for (name, definition) in params(kind) {
            if spec.get(name).is_none() {
                let example = definition
                    .get("default")
                    .or_else(|| definition["oneOf"][0].get("const"))
                    .unwrap_or_else(|| panic!("{kind}.{name}: no default and not required"));
                spec[name] = example.clone();
            }
        }
        validate_tag(&in_entry(spec.clone())).unwrap_or_else(|e| panic!("{kind}: {e}"));
        let typed: BehaviorSpec = serde_json::from_value(spec).unwrap();
        let written = serde_json::to_value(&typed).unwrap();
        let mut written: Vec<&String> = written.as_object().unwrap().keys().collect();
        let behavior = "behavior".to_owned();
        let mut declared: Vec<&String> = params(kind).keys().collect();
        declared.push(&behavior);
        written.sort();
        declared.sort();
        assert_eq!(written, declared, "{kind}");
    }
}

#[test]
fn every_parameter_says_its_unit_or_is_a_ratio_and_is_bounded() {
    for kind in BehaviorKind::ALL {
        for (name, definition) in params(kind) {
            let description = definition["description"].as_str().unwrap_or_default();
            assert!(!description.is_empty(), "{kind}.{name}: no description");
            if definition["type"] == "number" {
                let has_upper = definition.get("maximum").is_some();
                let has_lower = definition.get("minimum").is_some()
                    || definition.get("exclusiveMinimum").is_some();
                assert!(has_upper && has_lower, "{kind}.{name}: unbounded");
                let unit = definition["x-unit"].as_str();
                let unitless = description.contains("fraction") || description.contains("0 to 1");
                assert!(unit.is_some() || unitless, "{kind}.{name}: no unit");
                if let Some(unit) = unit {
                    let word = match unit {
                        "N" => "newtons",
                        "m" => "metres",
                        "degrees" => "degrees",
                        other => panic!("{kind}.{name}: unexpected unit {other}"),
                    };
                    assert!(description.contains(word), "{kind}.{name}: {description}");
                }
            }
        }
    }
}

#[test]
fn no_force_is_allowed_to_reach_a_dangerous_level() {
    for kind in BehaviorKind::ALL {
        for (name, definition) in params(kind) {
            if definition["x-unit"] == "N" {
                let maximum = definition["maximum"].as_f64().unwrap();
                assert!(maximum <= 25.0, "{kind}.{name}: {maximum} N");
                let mut spec = minimal(kind);
                spec[name] = json!(500.0);
                let errors = validate_tag(&in_entry(spec)).unwrap_err();
                let at = format!("/behaviors/b/{name}");
                assert_eq!(errors.at(&at).count(), 1, "{kind}.{name}: {errors}");
            }
        }
    }
}
