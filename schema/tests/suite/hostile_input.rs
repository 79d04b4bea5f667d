//! Hostile input at the contract's boundary: whatever a client sends, parsing an EPC and
//! validating an entry, trial or robot never panic, and every rejection is usable: a non-empty
//! list of problems, each with a message and a JSON pointer into the document that was sent.
//!
//! `src/epc/tests.rs` already covers arbitrary strings and URI-shaped input for `Epc::parse`;
//! this file adds exact acceptance of hex by length, look-alike digits, raw bytes and sizes far
//! beyond any EPC.

use pps_schema::{Epc, EpcError, Robot, TagEntry, Trial, ValidationErrors};
use proptest::prelude::*;
use proptest::sample::Index;
use serde_json::{Map, Value, json};

/// Longer error messages would mean the input is echoed back whole.
const MAX_MESSAGE: usize = 400;

proptest! {
    #[test]
    fn epc_hex_is_accepted_exactly_in_whole_words_of_4_to_124_digits(
        hex in "[0-9a-fA-F]{0,200}",
        before in "[ \t\r\n]{0,3}",
        after in "[ \t\r\n]{0,3}",
    ) {
        let parsed = Epc::parse(&format!("{before}{hex}{after}"));
        let len = hex.len();
        if (4..=124).contains(&len) && len % 4 == 0 {
            let epc = parsed.unwrap();
            prop_assert_eq!(epc.as_hex(), hex.to_ascii_uppercase());
        } else if len == 0 {
            prop_assert_eq!(parsed.unwrap_err(), EpcError::Empty);
        } else {
            prop_assert_eq!(parsed.unwrap_err(), EpcError::Length(len));
        }
    }

    /// Unicode has digits and letters that look like hex but are not: each is named, with its
    /// position counted in characters.
    #[test]
    fn epc_look_alike_digits_are_named_where_they_are(
        hex in "[0-9A-F]{8}",
        at in 0usize..8,
        look_alike in prop::sample::select(vec!['０', '９', 'Ａ', 'ｆ', '٣', '۷', '߀', '১', 'Ⅰ', 'ß', 'ǅ', '\u{200b}']),
    ) {
        let mut chars: Vec<char> = hex.chars().collect();
        chars[at] = look_alike;
        let input: String = chars.into_iter().collect();
        prop_assert_eq!(
            Epc::parse(&input).unwrap_err(),
            EpcError::NotHex { found: look_alike, position: at + 1 }
        );
    }

    #[test]
    fn epc_raw_bytes_never_panic_and_are_answered_briefly(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        let input = String::from_utf8_lossy(&bytes);
        match Epc::parse(&input) {
            Ok(epc) => prop_assert_eq!(Epc::parse(epc.as_hex()).unwrap(), epc),
            Err(error) => {
                let message = error.to_string();
                prop_assert!(!message.trim().is_empty());
                prop_assert!(message.chars().count() < MAX_MESSAGE, "{}", message);
            }
        }
    }
}

#[test]
fn epc_input_far_beyond_any_epc_is_refused_briefly() {
    for len in [125, 128, 4096, 1 << 20] {
        let hex = "A".repeat(len);
        assert_eq!(Epc::parse(&hex).unwrap_err(), EpcError::Length(len));
        let inputs = [
            format!("urn:epc:tag:sgtin-96:3.{hex}.1.1"),
            format!("urn:epc:tag:{hex}"),
            format!("{hex}é"),
            "é".repeat(len),
            format!("urn:epc:id:{}", "%".repeat(len)),
        ];
        for input in inputs {
            let message = Epc::parse(&input).expect_err("refused").to_string();
            assert!(message.chars().count() < MAX_MESSAGE, "{len}: {message}");
        }
    }
}

/// Any JSON document, with keys a validator has opinions about and keys that need escaping in a
/// JSON pointer.
fn any_json() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::from),
        any::<i64>().prop_map(Value::from),
        any::<f64>()
            .prop_filter("JSON numbers are finite", |f| f.is_finite())
            .prop_map(Value::from),
        prop_oneof![Just(-1e300), Just(0.0), Just(500.0), Just(1e-300)].prop_map(Value::from),
        "\\PC{0,12}".prop_map(Value::from),
        prop::sample::select(vec![
            "light_switch",
            "push",
            "el-e",
            "on",
            "355AB1C60000002000000001"
        ])
        .prop_map(Value::from),
    ];
    leaf.prop_recursive(4, 48, 5, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..5).prop_map(Value::Array),
            prop::collection::vec((key(), inner), 0..5)
                .prop_map(|pairs| Value::Object(pairs.into_iter().collect())),
        ]
    })
}

fn key() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "epc",
            "properties",
            "actions",
            "behaviors",
            "links",
            "robots",
            "behavior",
            "name",
            "type",
            "el-e",
            "force_threshold",
            "id",
            "robot",
            "forces",
            "capabilities",
            "limits",
            "a/b",
            "~0",
            "~1",
            "",
            " ",
            "revision",
        ])
        .prop_map(String::from),
        "\\PC{0,6}",
    ]
}

/// Every JSON pointer into `value`, the document itself first.
fn pointers(value: &Value, at: String, into: &mut Vec<String>) {
    into.push(at.clone());
    match value {
        Value::Object(object) => {
            for (key, child) in object {
                pointers(child, format!("{at}/{}", pps_schema::pointer::escape(key)), into);
            }
        }
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                pointers(item, format!("{at}/{i}"), into);
            }
        }
        _ => {}
    }
}

/// One change a careless or hostile client might make to a valid document.
#[derive(Debug, Clone)]
enum Mutation {
    Replace(Index, Value),
    Remove(Index),
    Add(Index, String, Value),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<Index>(), any_json()).prop_map(|(at, value)| Mutation::Replace(at, value)),
        any::<Index>().prop_map(Mutation::Remove),
        (any::<Index>(), key(), any_json())
            .prop_map(|(at, key, value)| Mutation::Add(at, key, value)),
    ]
}

fn mutate(document: &mut Value, mutation: &Mutation) {
    let mut all = Vec::new();
    pointers(document, String::new(), &mut all);
    let (Mutation::Replace(at, _) | Mutation::Remove(at) | Mutation::Add(at, ..)) = mutation;
    let pointer = at.get(&all).clone();
    match mutation {
        Mutation::Replace(_, value) => *document.pointer_mut(&pointer).unwrap() = value.clone(),
        Mutation::Remove(_) => {
            let Some((parent, last)) = pointer.rsplit_once('/') else { return };
            let key = pps_schema::pointer::unescape(last);
            match document.pointer_mut(parent).unwrap() {
                Value::Object(object) => {
                    object.remove(&key);
                }
                Value::Array(items) => {
                    items.remove(key.parse::<usize>().unwrap());
                }
                _ => unreachable!("a pointer's parent holds it"),
            }
        }
        Mutation::Add(_, key, value) => match document.pointer_mut(&pointer).unwrap() {
            Value::Object(object) => {
                object.insert(key.clone(), value.clone());
            }
            Value::Array(items) => items.push(value.clone()),
            other => *other = value.clone(),
        },
    }
}

/// What every rejection must be: problems listed, each worded, each at a place in `document`
/// or at a missing field of an object that is there.
fn check_rejection(document: &Value, errors: &ValidationErrors) -> Result<(), TestCaseError> {
    prop_assert!(!errors.is_empty(), "a rejection lists at least one problem");
    for error in errors.errors() {
        prop_assert!(!error.message.trim().is_empty(), "{:?}", error);
        prop_assert!(
            error.pointer.is_empty() || error.pointer.starts_with('/'),
            "not a JSON pointer: {:?}",
            error
        );
        if document.pointer(&error.pointer).is_some() {
            continue;
        }
        let (parent, last) = error.pointer.rsplit_once('/').unwrap_or(("", &error.pointer));
        let missing = pps_schema::pointer::unescape(last);
        let parent = document.pointer(parent).and_then(Value::as_object);
        prop_assert!(
            parent.is_some_and(|object: &Map<String, Value>| !object.contains_key(&missing)),
            "{:?} is neither in the document nor a missing field of an object in it: {}",
            error,
            document
        );
    }
    Ok(())
}

fn seed_entry() -> Value {
    serde_json::from_str(include_str!("../../../seed_tags/ada_light_switch.json")).unwrap()
}

fn seed_trial() -> Value {
    json!({
        "id": "67e55044-10b1-426f-9247-bb680e5fe0c8", "epc": "355AB1C60000002000000001",
        "robot": "el-e-1", "action": "on", "behavior": "push_top",
        "started_at": "2024-05-01T12:00:00Z", "finished_at": "2024-05-01T12:00:41Z",
        "outcome": "success", "confirmed": null, "detector": {}, "measurements": {},
        "forces": [{ "t": 0.0, "finger": "left", "force": [0.1, 0.0, 2.1] }],
        "start_pose": { "x": 1.5, "y": -0.2, "yaw": 3.1 }
    })
}

fn seed_robot() -> Value {
    json!({ "id": "el-e-1", "class": "el-e", "name": "EL-E",
            "capabilities": ["light_switch", "push"], "limits": { "max_force": 15.0 } })
}

/// Validates `document` as each kind; what validates must also read into its type, or the
/// server would store what it cannot use.
fn check_every_kind(document: &Value) -> Result<(), TestCaseError> {
    match pps_schema::validate_tag(document) {
        Ok(()) => {
            let mut entry = document.clone();
            pps_schema::strip_read_only(&mut entry);
            let typed = serde_json::from_value::<TagEntry>(entry);
            prop_assert!(typed.is_ok(), "valid but untyped: {:?} {}", typed.err(), document);
        }
        Err(errors) => check_rejection(document, &errors)?,
    }
    match pps_schema::validate_trial(document) {
        Ok(()) => {
            let typed = serde_json::from_value::<Trial>(document.clone());
            prop_assert!(typed.is_ok(), "valid but untyped: {:?} {}", typed.err(), document);
        }
        Err(errors) => check_rejection(document, &errors)?,
    }
    match pps_schema::validate_robot(document) {
        Ok(()) => {
            let typed = serde_json::from_value::<Robot>(document.clone());
            prop_assert!(typed.is_ok(), "valid but untyped: {:?} {}", typed.err(), document);
        }
        Err(errors) => check_rejection(document, &errors)?,
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn any_json_is_validated_without_panic_into_usable_problems(document in any_json()) {
        check_every_kind(&document)?;
    }

    #[test]
    fn mutated_entries_are_validated_into_usable_problems(
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let mut entry = seed_entry();
        for mutation in &mutations {
            mutate(&mut entry, mutation);
        }
        check_every_kind(&entry)?;
    }

    #[test]
    fn mutated_trials_and_robots_are_validated_into_usable_problems(
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        for seed in [seed_trial(), seed_robot()] {
            let mut document = seed;
            for mutation in &mutations {
                mutate(&mut document, mutation);
            }
            check_every_kind(&document)?;
        }
    }
}
