//! The schemas of the OpenAPI document: the contract's JSON Schemas, moved in so their `$ref`s
//! resolve inside the document, and the schemas of the registry's own answers, derived from the
//! types that serialise them (`crate::answers`).
//!
//! The contract schemas are taken from `pps-schema` as they are served; nothing here may restate
//! a rule of theirs.

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, SchemaGenerator};
use serde_json::{Map, Value};

pub use crate::answers::contract::SCHEMAS;
use crate::answers::{accounts, effective, inbox, meta, robots, stats, tags, tasks, trials};
use crate::error::Problem;
use crate::http;
use crate::http::page::Page;

/// Every schema of the document, by name.
pub fn schemas() -> Map<String, Value> {
    let mut schemas = Map::new();
    for name in pps_schema::SCHEMA_NAMES {
        if let Some(document) = pps_schema::schema_document(name) {
            schemas.insert((*name).to_owned(), contract_component(name, document));
        }
    }
    schemas.extend(answers());
    schemas.extend(request_bodies());
    schemas
}

/// A generator of components for what the registry sends (`for_serialize`) or reads.
fn generator(settings: SchemaSettings) -> SchemaGenerator {
    settings
        .with(|settings| {
            settings.definitions_path = "/components/schemas".into();
            settings.meta_schema = None;
        })
        .into_generator()
}

/// The schemas of every answer the routes name, and of what those refer to, by name.
fn answers() -> Map<String, Value> {
    let mut generator = generator(SchemaSettings::draft2020_12().for_serialize());
    add::<Problem<'static>>(&mut generator);
    add::<tags::StoredTagAnswer>(&mut generator);
    add::<tags::TagRevisionAnswer>(&mut generator);
    add::<tags::ValidationResult>(&mut generator);
    add::<stats::TagStats>(&mut generator);
    add::<robots::StoredRobotAnswer>(&mut generator);
    add::<effective::EffectiveEntry>(&mut generator);
    add::<inbox::InboxAnswer>(&mut generator);
    add::<trials::StoredTrialAnswer>(&mut generator);
    add::<tasks::TaskAnswer>(&mut generator);
    add::<accounts::TokenAnswer>(&mut generator);
    add::<accounts::MintedTokenAnswer>(&mut generator);
    add::<accounts::RevokedToken>(&mut generator);
    add::<accounts::SessionAnswer>(&mut generator);
    add::<accounts::UserAnswer>(&mut generator);
    add::<meta::Health>(&mut generator);
    add::<meta::HomeAssistantBridge>(&mut generator);
    add::<meta::JsonSchemaDocument>(&mut generator);
    add::<meta::OpenApiDocument>(&mut generator);
    // The lists: `Reply::page` names each as `<item>_page`.
    add::<Page<tags::StoredTagAnswer>>(&mut generator);
    add::<Page<tags::TagRevisionAnswer>>(&mut generator);
    add::<Page<robots::StoredRobotAnswer>>(&mut generator);
    add::<Page<inbox::InboxAnswer>>(&mut generator);
    add::<Page<trials::StoredTrialAnswer>>(&mut generator);
    add::<Page<tasks::TaskAnswer>>(&mut generator);
    add::<Page<accounts::TokenAnswer>>(&mut generator);
    add::<Page<accounts::UserAnswer>>(&mut generator);
    generator.take_definitions(true)
}

/// The schemas of the request bodies that are not contract documents, by name.
fn request_bodies() -> Map<String, Value> {
    let mut generator = generator(SchemaSettings::draft2020_12().for_deserialize());
    add::<http::retag::RetagBody>(&mut generator);
    add::<crate::tasks::request::NewTask>(&mut generator);
    add::<http::tasks::lease::Finish>(&mut generator);
    add::<http::tasks::decline::DeclineBody>(&mut generator);
    add::<http::trials::VerdictPatch>(&mut generator);
    add::<http::tokens::NewToken>(&mut generator);
    add::<http::session::Login>(&mut generator);
    add::<http::users::NewUser>(&mut generator);
    add::<http::users::PasswordChange>(&mut generator);
    add::<http::users::UserNameText>(&mut generator);
    generator.take_definitions(true)
}

/// Adds `T` (and what it refers to) to the generator's components.
fn add<T: JsonSchema>(generator: &mut SchemaGenerator) {
    generator.subschema_for::<T>();
}

/// A contract schema as a component: its own `$id` and `$schema` go (the document's dialect is
/// 2020-12 already, and an `$id` would re-base its references away from the document), and every
/// `$ref` is rewritten to point into `#/components/schemas/`.
fn contract_component(name: &str, document: &Value) -> Value {
    let mut component = document.clone();
    if let Some(object) = component.as_object_mut() {
        object.remove("$id");
        object.remove("$schema");
    }
    rewrite_refs(&mut component, name);
    component
}

fn rewrite_refs(value: &mut Value, home: &str) {
    match value {
        Value::Object(object) => {
            for (key, child) in object.iter_mut() {
                match child {
                    Value::String(reference) if key == "$ref" => {
                        *reference = in_document(reference, home);
                    }
                    _ => rewrite_refs(child, home),
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(|item| rewrite_refs(item, home)),
        _ => {}
    }
}

/// `#/$defs/x` in `home`, `other.schema.json#/$defs/x` or `other.schema.json`, as a pointer
/// into the document.
fn in_document(reference: &str, home: &str) -> String {
    let (file, fragment) = reference.split_once('#').unwrap_or((reference, ""));
    let target = match file.strip_suffix(".schema.json") {
        Some(other) => other,
        None if file.is_empty() => home,
        // Not one of ours: left for the test that resolves every reference to flag.
        None => return reference.to_owned(),
    };
    format!("{SCHEMAS}{target}{fragment}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_point_into_the_document() {
        assert_eq!(in_document("#/$defs/epc", "tag"), "#/components/schemas/tag/$defs/epc");
        assert_eq!(
            in_document("robot.schema.json#/$defs/robot_id", "trial"),
            "#/components/schemas/robot/$defs/robot_id"
        );
        assert_eq!(in_document("drop.schema.json", "tag"), "#/components/schemas/drop");
    }

    #[test]
    fn contract_components_lose_their_id_and_keep_their_rules() {
        let tag = &schemas()["tag"];
        assert!(tag.get("$id").is_none() && tag.get("$schema").is_none());
        assert_eq!(tag["properties"]["epc"]["$ref"], "#/components/schemas/tag/$defs/epc");
        assert_eq!(tag["additionalProperties"], false);
    }
}
