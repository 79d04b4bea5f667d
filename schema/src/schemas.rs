//! The JSON Schema documents of the contract, embedded in the binary and served as they are
//! by `GET /api/v1/schema/{name}`.

use std::sync::LazyLock;

use serde_json::Value;

/// Every schema's `$id` is this base followed by `<name>.schema.json`; `$ref`s between the
/// files are relative to it.
pub const SCHEMA_BASE_URI: &str = "https://pps-tags.org/schema/";

const SOURCES: [(&str, &str); 8] = [
    ("tag", include_str!("../schemas/tag.schema.json")),
    ("trial", include_str!("../schemas/trial.schema.json")),
    ("robot", include_str!("../schemas/robot.schema.json")),
    ("light_switch", include_str!("../schemas/light_switch.schema.json")),
    ("pull_back", include_str!("../schemas/pull_back.schema.json")),
    ("push", include_str!("../schemas/push.schema.json")),
    ("pull_lamp", include_str!("../schemas/pull_lamp.schema.json")),
    ("drop", include_str!("../schemas/drop.schema.json")),
];

/// The names [`schema_document`] knows, in the order above.
pub const SCHEMA_NAMES: &[&str] = &{
    let mut names = [""; SOURCES.len()];
    let mut i = 0;
    while i < SOURCES.len() {
        names[i] = SOURCES[i].0;
        i += 1;
    }
    names
};

/// One parsed schema.
#[derive(Debug)]
pub(crate) struct SchemaDocument {
    pub name: &'static str,
    pub id: String,
    pub document: Value,
}

static DOCUMENTS: LazyLock<Vec<SchemaDocument>> = LazyLock::new(|| {
    SOURCES
        .iter()
        .map(|(name, source)| SchemaDocument {
            name,
            id: format!("{SCHEMA_BASE_URI}{name}.schema.json"),
            // The sources are part of this crate: a parse failure is a build defect, which
            // the tests catch before anything ships.
            document: serde_json::from_str(source)
                .unwrap_or_else(|e| panic!("schemas/{name}.schema.json is not JSON: {e}")),
        })
        .collect()
});

pub(crate) fn documents() -> &'static [SchemaDocument] {
    &DOCUMENTS
}

/// The schema called `name` (one of [`SCHEMA_NAMES`]), e.g. `"tag"` or `"light_switch"`.
pub fn schema_document(name: &str) -> Option<&'static Value> {
    documents().iter().find(|doc| doc.name == name).map(|doc| &doc.document)
}

/// The document whose `$id` is `id`.
pub(crate) fn document_by_id(id: &str) -> Option<&'static SchemaDocument> {
    documents().iter().find(|doc| doc.id == id)
}

/// What `reference` (a `$ref` value) points to, seen from the document `from`.
pub(crate) fn resolve(
    from: &'static SchemaDocument,
    reference: &str,
) -> Option<(&'static SchemaDocument, &'static Value)> {
    let (path, fragment) = reference.split_once('#').unwrap_or((reference, ""));
    let document =
        if path.is_empty() { from } else { document_by_id(&format!("{SCHEMA_BASE_URI}{path}"))? };
    Some((document, document.document.pointer(&percent_decode(fragment))?))
}

/// The schema object holding the keyword at `location`, an absolute keyword location such as
/// `https://pps-tags.org/schema/push.schema.json#/$defs/params/properties/stop_force/maximum`.
pub(crate) fn keyword_parent(location: &str) -> Option<(&'static SchemaDocument, &'static Value)> {
    let (id, fragment) = location.split_once('#')?;
    let document = document_by_id(id)?;
    let pointer = percent_decode(fragment);
    let parent = pointer.rsplit_once('/').map_or("", |(parent, _)| parent);
    Some((document, document.document.pointer(parent)?))
}

/// URI fragments may percent-encode characters such as `$`; JSON pointers do not.
fn percent_decode(fragment: &str) -> String {
    let bytes = fragment.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                decoded.push(byte);
                i += 3;
            }
            (byte, _) => {
                decoded.push(byte);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&decoded).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_has_a_titled_described_2020_12_document() {
        assert_eq!(
            SCHEMA_NAMES,
            ["tag", "trial", "robot", "light_switch", "pull_back", "push", "pull_lamp", "drop"]
        );
        for name in SCHEMA_NAMES {
            let doc = schema_document(name).unwrap();
            assert_eq!(doc["$schema"], "https://json-schema.org/draft/2020-12/schema", "{name}");
            assert_eq!(doc["$id"], format!("https://pps-tags.org/schema/{name}.schema.json"));
            assert!(doc["title"].as_str().is_some_and(|t| !t.is_empty()), "{name}");
            assert!(doc["description"].as_str().is_some_and(|d| d.len() > 20), "{name}");
        }
        assert_eq!(schema_document("tags"), None);
        assert_eq!(schema_document(""), None);
    }

    #[test]
    fn resolves_local_and_cross_document_references() {
        let tag = document_by_id("https://pps-tags.org/schema/tag.schema.json").unwrap();
        let (doc, epc) = resolve(tag, "#/$defs/epc").unwrap();
        assert_eq!(doc.name, "tag");
        assert!(epc["pattern"].is_string());
        let (doc, id) = resolve(tag, "robot.schema.json#/$defs/robot_id").unwrap();
        assert_eq!(doc.name, "robot");
        assert!(id["pattern"].is_string());
        let (doc, root) = resolve(tag, "drop.schema.json").unwrap();
        assert_eq!((doc.name, &root["title"]), ("drop", &"Drop behaviour".into()));
        assert!(resolve(tag, "nothing.schema.json").is_none());
    }

    #[test]
    fn finds_the_schema_object_of_a_keyword() {
        let (doc, parent) = keyword_parent(
            "https://pps-tags.org/schema/push.schema.json#/%24defs/params/properties/stop_force/maximum",
        )
        .unwrap();
        assert_eq!(doc.name, "push");
        assert_eq!(parent["x-unit"], "N");
    }
}
