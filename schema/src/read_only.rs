//! Fields the registry writes and clients must not: shown on GET, ignored on PUT.

use serde_json::Value;

/// Top-level fields the registry adds to a tag entry on GET.
pub const READ_ONLY_TAG_FIELDS: &[&str] =
    &["epc_uri", "revision", "updated_at", "updated_by", "archived"];

/// Top-level fields the registry adds to a trial.
pub const READ_ONLY_TRIAL_FIELDS: &[&str] = &["received_at", "seq", "picture"];

/// Top-level fields the registry adds to a robot.
pub const READ_ONLY_ROBOT_FIELDS: &[&str] = &["last_seen"];

/// Removes the registry's read-only fields from a tag entry, so that an entry fetched with
/// GET, edited and PUT back is stored exactly as the caretaker left the rest.
pub fn strip_read_only(entry: &mut Value) {
    strip_fields(entry, READ_ONLY_TAG_FIELDS);
}

/// Removes `fields` from the top level of `document` (a no-op on anything but an object).
pub fn strip_fields(document: &mut Value, fields: &[&str]) {
    if let Value::Object(object) = document {
        for field in fields {
            object.remove(*field);
        }
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    #[test]
    fn get_edit_put_round_trips() {
        let mut fetched = json!({
            "epc": "355AB1C60000003000000001",
            "epc_uri": "urn:epc:id:gid:95100000.3.1",
            "revision": 4,
            "updated_at": "2024-05-01T12:00:00Z",
            "updated_by": "ann",
            "archived": false,
            "properties": {"name": "lamp 1", "revision": "kept: not top level"},
            "actions": {"on": "pull_chain"},
            "behaviors": {"pull_chain": {"behavior": "pull_lamp"}}
        });
        strip_read_only(&mut fetched);
        assert_eq!(
            fetched,
            json!({
                "epc": "355AB1C60000003000000001",
                "properties": {"name": "lamp 1", "revision": "kept: not top level"},
                "actions": {"on": "pull_chain"},
                "behaviors": {"pull_chain": {"behavior": "pull_lamp"}}
            })
        );
        crate::validate::validate_tag(&fetched).unwrap();
    }

    #[test]
    fn read_only_fields_are_declared_read_only_in_the_schemas() {
        for (schema, fields) in [
            ("tag", READ_ONLY_TAG_FIELDS),
            ("trial", READ_ONLY_TRIAL_FIELDS),
            ("robot", READ_ONLY_ROBOT_FIELDS),
        ] {
            let document = crate::schemas::schema_document(schema).unwrap();
            for field in fields {
                assert_eq!(
                    document["properties"][field]["readOnly"],
                    json!(true),
                    "{schema}.{field}"
                );
            }
            let declared = document["properties"].as_object().unwrap();
            let marked = declared.values().filter(|p| p["readOnly"] == json!(true));
            assert_eq!(marked.count(), fields.len(), "{schema}");
        }
    }
}
