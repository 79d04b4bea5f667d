//! What a caretaker sees when PUTting a tag entry: every problem at once, each at its field.

use pps_schema::{FieldError, TagEntry, ValidationErrors, validate_tag};
use serde_json::{Value, json};

fn rejected(entry: &Value) -> ValidationErrors {
    validate_tag(entry).expect_err("the entry must be rejected")
}

fn pointers(errors: &ValidationErrors) -> Vec<&str> {
    errors.errors().iter().map(|e| e.pointer.as_str()).collect()
}

fn message_at<'a>(errors: &'a ValidationErrors, pointer: &'a str) -> &'a str {
    let found: Vec<&FieldError> = errors.at(pointer).collect();
    assert_eq!(found.len(), 1, "one error at {pointer} in {errors}");
    &found[0].message
}

/// A small valid entry to break one field at a time.
fn lamp() -> Value {
    json!({
        "epc": "355AB1C60000003000000001",
        "properties": {"type": "lamp", "name": "lamp 1"},
        "actions": {"on": "pull_chain"},
        "behaviors": {"pull_chain": {"behavior": "pull_lamp"}}
    })
}

fn with(mut entry: Value, pointer: &str, value: Value) -> Value {
    let (parent, key) = pointer.rsplit_once('/').unwrap();
    entry.pointer_mut(parent).unwrap()[key] = value;
    entry
}

#[test]
fn the_design_example_validates_and_reads() {
    let example = json!({
      "epc": "E20034120000000000001001",
      "properties": {
        "type": "ada light switch", "name": "A D A light switch 1", "pps_tag": "dycem",
        "change": "overall_brightness", "direction": "up",
        "height": 1.22, "on_plane": true, "switch_travel": 0.02,
        "location": { "room": "hallway" },
        "robots": { "el-e": { "color_segmentation": { "hue_deg": [340, 20], "saturation": [0.6, 1.0], "value": [0.15, 1.0] } } }
      },
      "actions": { "on": "push_top", "off": "push_bottom" },
      "behaviors": {
        "push_top":    { "behavior": "light_switch", "force_threshold": 3.0, "height_offset":  0.02, "robots": { "el-e": { "gripper_deg": 5 } } },
        "push_bottom": { "behavior": "light_switch", "force_threshold": 3.0, "height_offset": -0.02, "robots": { "el-e": { "gripper_deg": 5 } } }
      },
      "links": [ { "rel": "controls", "target": "E20034120000000000002001", "note": "ceiling light" } ]
    });
    validate_tag(&example).unwrap();
    let entry: TagEntry = serde_json::from_value(example).unwrap();
    assert_eq!(entry.links[0].note.as_deref(), Some("ceiling light"));
    assert_eq!(
        entry.properties.robots["el-e"].color_segmentation,
        Some(pps_schema::ColorSegmentation::default())
    );
}

#[test]
fn one_call_reports_every_problem_at_its_field() {
    let bad = json!({
        "epc": "355AB1C60000009000000001",
        "colour": "red",
        "properties": {"type": "ada light switch"},
        "actions": {"on": "push_top", "off": "push_bottm"},
        "behaviors": {"push_top": {"behavior": "light_switch", "force_threshold": 500}}
    });
    let errors = rejected(&bad);
    assert_eq!(
        pointers(&errors),
        ["/actions/off", "/behaviors/push_top/force_threshold", "/colour", "/properties/name"],
        "{errors}"
    );
    let missing = message_at(&errors, "/actions/off");
    assert!(missing.contains("\"push_bottm\"") && missing.contains("push_top"), "{missing}");
    let force = message_at(&errors, "/behaviors/push_top/force_threshold");
    assert!(force.contains("500 N") && force.contains("20 N"), "{force}");
    let unknown = message_at(&errors, "/colour");
    assert!(unknown.contains("colour") && unknown.contains("behaviors"), "{unknown}");
    assert!(message_at(&errors, "/properties/name").contains("name is required"));
}

#[test]
fn errors_serialize_as_pointer_and_message() {
    let errors = rejected(&with(lamp(), "/properties/height", json!(9)));
    assert_eq!(
        serde_json::to_value(&errors).unwrap(),
        json!([{"pointer": "/properties/height", "message": "height is 9 m, above the maximum of 2.5 m."}])
    );
}

#[test]
fn unknown_properties_are_kept_but_known_ones_are_typed() {
    let entry = with(lamp(), "/properties/bulb", json!({"watts": 40}));
    validate_tag(&entry).unwrap();
    let typed: TagEntry = serde_json::from_value(entry.clone()).unwrap();
    assert_eq!(typed.properties.other["bulb"], json!({"watts": 40}));
    assert_eq!(serde_json::to_value(&typed.properties).unwrap(), entry["properties"]);

    let errors = rejected(&with(lamp(), "/properties/pps_tag", json!("felt")));
    let message = message_at(&errors, "/properties/pps_tag");
    assert!(message.contains("\"foam_tube\""), "{message}");
}

#[test]
fn an_override_holds_only_the_behaviours_own_parameters() {
    let entry = with(
        lamp(),
        "/behaviors/pull_chain/robots",
        json!({"el-e": {"grip_force": 2.5, "colour": "red", "behavior": "push", "robots": {}}}),
    );
    let errors = rejected(&entry);
    assert_eq!(
        pointers(&errors),
        [
            "/behaviors/pull_chain/robots/el-e/behavior",
            "/behaviors/pull_chain/robots/el-e/colour",
            "/behaviors/pull_chain/robots/el-e/robots",
        ],
        "{errors}"
    );
    let message = message_at(&errors, "/behaviors/pull_chain/robots/el-e/colour");
    assert!(message.contains("grip_force") && message.contains("max_pull_force"), "{message}");

    let too_strong =
        with(lamp(), "/behaviors/pull_chain/robots", json!({"el-e": {"max_pull_force": 60}}));
    let errors = rejected(&too_strong);
    let message = message_at(&errors, "/behaviors/pull_chain/robots/el-e/max_pull_force");
    assert!(message.contains("60 N"), "{message}");
}

#[test]
fn override_keys_are_robot_classes_or_ids() {
    let entry = with(lamp(), "/behaviors/pull_chain/robots", json!({"EL E": {}}));
    let errors = rejected(&entry);
    let message = message_at(&errors, "/behaviors/pull_chain/robots/EL E");
    assert!(message.contains("lower-case"), "{message}");
}

#[test]
fn unknown_behaviour_is_one_precise_error() {
    let errors = rejected(&with(lamp(), "/behaviors/pull_chain/behavior", json!("pull_door")));
    assert_eq!(pointers(&errors), ["/behaviors/pull_chain/behavior"], "{errors}");
    assert!(errors.errors()[0].message.contains("\"pull_lamp\""));
}

#[test]
fn each_behaviour_is_checked_against_its_own_schema() {
    let entry = with(
        lamp(),
        "/behaviors",
        json!({
            "pull_chain": {"behavior": "pull_lamp", "push_distance": 0.3},
            "drawer": {"behavior": "pull_back"},
            "switch": {"behavior": "light_switch", "motion": "flip"},
            "rocker": {"behavior": "light_switch", "motion": "press", "gripper_deg": 120},
            "bin": {"behavior": "drop", "standoff": 0.05}
        }),
    );
    let errors = rejected(&entry);
    assert_eq!(
        pointers(&errors),
        [
            "/behaviors/bin/standoff",
            "/behaviors/drawer/pull_distance",
            "/behaviors/pull_chain/push_distance",
            "/behaviors/rocker/gripper_deg",
            "/behaviors/switch/direction",
        ],
        "{errors}"
    );
    assert!(message_at(&errors, "/behaviors/rocker/gripper_deg").contains("90 degrees"));
    assert!(message_at(&errors, "/behaviors/bin/standoff").contains("0.2 m"));
}

#[test]
fn an_entry_needs_at_least_one_action_and_behaviour() {
    let entry = with(with(lamp(), "/actions", json!({})), "/behaviors", json!({}));
    let errors = rejected(&entry);
    assert_eq!(pointers(&errors), ["/actions", "/behaviors"], "{errors}");
}

#[test]
fn the_epc_is_hex_of_whole_words() {
    for bad in ["", "355", "355AB", "355AB1C60000003000000001X", "urn:epc:id:gid:1.2.3"] {
        let errors = rejected(&with(lamp(), "/epc", json!(bad)));
        assert_eq!(pointers(&errors), ["/epc"], "{bad}: {errors}");
        assert!(errors.errors()[0].message.contains("16-bit words"), "{errors}");
    }
    validate_tag(&with(lamp(), "/epc", json!("355ab1c60000003000000001"))).unwrap();
    validate_tag(&with(lamp(), "/epc", json!("ABCD"))).unwrap();
    validate_tag(&with(lamp(), "/epc", json!("A".repeat(124)))).unwrap();
    rejected(&with(lamp(), "/epc", json!("A".repeat(128))));
}

#[test]
fn a_link_names_another_tag() {
    let entry = with(
        lamp(),
        "/links",
        json!([
            {"rel": "near", "target": "355ab1c60000003000000001"},
            {"rel": "controlled_by", "target": "355AB1C60000001000000001"},
            {"rel": "owns", "target": "355AB1C60000001000000001"}
        ]),
    );
    let errors = rejected(&entry);
    assert_eq!(pointers(&errors), ["/links/0/target", "/links/2/rel"], "{errors}");
    assert!(message_at(&errors, "/links/0/target").contains("own EPC"));
}

#[test]
fn colour_ranges_are_min_then_max_except_hue() {
    let segmentation = |hue: [f64; 2], saturation: [f64; 2], value: [f64; 2]| {
        with(
            lamp(),
            "/properties/robots",
            json!({"el-e": {"color_segmentation": {"hue_deg": hue, "saturation": saturation, "value": value}}}),
        )
    };
    validate_tag(&segmentation([340.0, 20.0], [0.6, 1.0], [0.15, 1.0])).unwrap();
    let errors = rejected(&segmentation([20.0, 400.0], [0.9, 0.6], [1.0, 0.15]));
    let at = "/properties/robots/el-e/color_segmentation";
    assert_eq!(
        pointers(&errors),
        [format!("{at}/hue_deg/1"), format!("{at}/saturation"), format!("{at}/value")],
        "{errors}"
    );
    assert!(message_at(&errors, &format!("{at}/saturation")).contains("[0.6, 0.9]"));
}

#[test]
fn read_only_fields_are_accepted_on_input() {
    let mut entry = lamp();
    entry["revision"] = json!(3);
    entry["epc_uri"] = json!(null);
    entry["updated_at"] = json!("2024-05-01T12:00:00Z");
    entry["updated_by"] = json!("ann");
    entry["archived"] = json!(false);
    validate_tag(&entry).unwrap();
    let typed: TagEntry = serde_json::from_value(entry).unwrap();
    assert_eq!(typed, serde_json::from_value::<TagEntry>(lamp()).unwrap());
}

#[test]
fn a_document_that_is_not_an_object_is_one_error_at_the_root() {
    let errors = rejected(&json!(["lamp"]));
    assert_eq!(pointers(&errors), [""]);
    assert!(errors.errors()[0].message.contains("an object"));
}

#[test]
fn a_tag_size_is_a_width_and_a_height_in_metres() {
    let entry = with(lamp(), "/properties/tag_size", json!({"width": 0.05, "height": 0.08}));
    validate_tag(&entry).unwrap();
    let typed: TagEntry = serde_json::from_value(entry).unwrap();
    let size = typed.properties.tag_size.expect("typed");
    assert!((size.reach() - 0.0472).abs() < 1e-4, "{}", size.reach());

    let errors = rejected(&with(lamp(), "/properties/tag_size", json!({"width": 5, "height": 0})));
    assert_eq!(
        pointers(&errors),
        ["/properties/tag_size/height", "/properties/tag_size/width"],
        "{errors}"
    );
    let errors = rejected(&with(lamp(), "/properties/tag_size", json!({"width": 0.05})));
    let message = message_at(&errors, "/properties/tag_size/height");
    assert!(message.contains("required"), "{message}");
}
