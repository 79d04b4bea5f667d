//! Answers about the registry itself: liveness, the Home Assistant bridge, and the documents
//! it publishes (which are described by their own standards, not here).

use std::borrow::Cow;

use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
use serde::Serialize;

use crate::home_assistant::Status;

/// The registry answers (or, for readiness, can take writes now).
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "health")]
pub struct Health {
    #[schemars(extend("const" = "ok"))]
    status: &'static str,
}

impl Health {
    pub const OK: Self = Self { status: "ok" };
}

/// The Home Assistant bridge, as this replica sees it.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "home_assistant_bridge")]
pub struct HomeAssistantBridge {
    pub bridge: Status,
    /// The broker's URL without its password; null when off.
    pub broker: Option<String>,
    /// Home Assistant's discovery prefix; null when off.
    pub prefix: Option<String>,
}

/// A JSON Schema (2020-12) document of the contract, as published.
#[derive(Debug)]
pub struct JsonSchemaDocument;

impl JsonSchema for JsonSchemaDocument {
    fn schema_name() -> Cow<'static, str> {
        "json_schema".into()
    }

    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "A JSON Schema (2020-12) document of the contract, as published.",
            "type": "object",
            "required": ["$schema", "$id"]
        })
    }
}

/// This document: OpenAPI 3.1, described by its own specification.
#[derive(Debug)]
pub struct OpenApiDocument;

impl JsonSchema for OpenApiDocument {
    fn schema_name() -> Cow<'static, str> {
        "openapi".into()
    }

    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "This document.",
            "type": "object",
            "required": ["openapi", "paths"]
        })
    }
}
