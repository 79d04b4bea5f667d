//! What a caretaker reads comes from the schemas: every field of a tag entry and of each
//! behaviour has a title, every allowed value has one too, and no help text shows markup.

use pps_schema::{BehaviorKind, schema_document};
use serde_json::Value;

/// The schemas a caretaker's form is built from.
fn caretaker_schemas() -> Vec<(&'static str, &'static Value)> {
    let mut names = vec!["tag"];
    names.extend(BehaviorKind::ALL.iter().map(|kind| kind.schema_name()));
    names.into_iter().map(|name| (name, schema_document(name).unwrap())).collect()
}

/// The node a local `$ref` ("#/$defs/x") names, or None for a reference to another document.
fn local<'a>(doc: &'a Value, node: &Value) -> Option<&'a Value> {
    let path = node["$ref"].as_str()?.strip_prefix("#/")?;
    path.split('/').try_fold(doc, |at, part| at.get(part))
}

/// Every schema under `schema` (itself included), with the path that leads to it, following
/// the keywords that hold schemas.
fn walk<'a>(schema: &'a Value, path: String, found: &mut Vec<(String, &'a Value)>) {
    if !schema.is_object() {
        return;
    }
    found.push((path.clone(), schema));
    for keyword in ["properties", "$defs"] {
        for (key, child) in schema[keyword].as_object().into_iter().flatten() {
            walk(child, format!("{path}/{keyword}/{key}"), found);
        }
    }
    for keyword in ["items", "additionalProperties", "propertyNames", "if", "then", "else"] {
        walk(&schema[keyword], format!("{path}/{keyword}"), found);
    }
    for keyword in ["allOf", "anyOf", "oneOf"] {
        for (i, child) in schema[keyword].as_array().into_iter().flatten().enumerate() {
            walk(child, format!("{path}/{keyword}/{i}"), found);
        }
    }
}

#[test]
fn every_field_has_a_title() {
    for (name, doc) in caretaker_schemas() {
        let mut nodes = Vec::new();
        walk(doc, String::new(), &mut nodes);
        for (path, node) in nodes {
            let Some(properties) = node.get("properties").and_then(Value::as_object) else {
                continue;
            };
            for (key, prop) in properties {
                if prop["readOnly"] == Value::Bool(true) || prop.get("const").is_some() {
                    continue;
                }
                let titled = prop["title"].is_string()
                    || local(doc, prop).is_some_and(|target| target["title"].is_string())
                    || prop["$ref"].as_str().is_some_and(|r| !r.starts_with('#'));
                assert!(titled, "{name}{path}/properties/{key} has no title");
            }
        }
    }
}

#[test]
fn every_allowed_value_has_a_title_and_no_help_shows_markup() {
    for (name, doc) in caretaker_schemas() {
        let mut nodes = Vec::new();
        walk(doc, String::new(), &mut nodes);
        for (path, node) in nodes {
            assert!(node.get("enum").is_none(), "{name}{path}: an enum without titles");
            if let Some(choices) = node.get("oneOf").and_then(Value::as_array) {
                for choice in choices {
                    assert!(
                        choice.get("const").is_some() && choice["title"].is_string(),
                        "{name}{path}: {choice} is not a titled value"
                    );
                }
            }
            if let Some(text) = node.get("description").and_then(Value::as_str) {
                assert!(!text.contains('`'), "{name}{path}: backticks in {text:?}");
            }
        }
    }
}
