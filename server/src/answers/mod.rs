//! What the registry answers: the typed shapes of the API's JSON bodies (and of the trial
//! export), one file per resource. Each type is serialised by serde and described by the JSON
//! Schema derived from the same type (`schemars`), so the OpenAPI document cannot drift from
//! what is sent; the doc comments of the fields are the schema's descriptions.
//!
//! Answers are built from store rows and decide nothing. They name no HTTP type (the command
//! line's exports write stored tags and trials with them too), and the store never uses them.

/// A type that stands for a schema written out rather than derived: a `$ref` to the contract,
/// a time, names taken from a constant, a document another standard describes. An `inline`
/// one is written where it is used; any other becomes the component `$name`.
macro_rules! written_schema {
    ($(#[$doc:meta])* $ty:ident, $name:expr, inline: $inline:expr, $schema:expr) => {
        $(#[$doc])*
        #[derive(Debug)]
        pub struct $ty;

        impl schemars::JsonSchema for $ty {
            fn inline_schema() -> bool {
                $inline
            }

            fn schema_name() -> std::borrow::Cow<'static, str> {
                $name.into()
            }

            fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
                $schema
            }
        }
    };
}
pub(crate) use written_schema;

pub mod accounts;
pub mod contract;
pub mod effective;
pub mod inbox;
pub mod meta;
pub mod robots;
pub mod stamp;
pub mod stats;
pub mod tags;
pub mod tasks;
pub mod trials;

use serde_json::{Map, Value};

/// A stored document as an object, without the keys the registry answers itself, so that
/// flattening it beside them never writes a key twice.
fn document_without(document: &Value, read_only: &[&str]) -> Map<String, Value> {
    let mut object = match document {
        Value::Object(object) => object.clone(),
        _ => Map::new(),
    };
    for key in read_only {
        object.remove(*key);
    }
    object
}
