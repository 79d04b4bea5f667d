//! Answers about the registry itself: liveness, the Home Assistant bridge, and the documents
//! it publishes (which are described by their own standards, not here).

use schemars::{JsonSchema, json_schema};
use serde::Serialize;

use crate::ops::bridge_status::Status;

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
    /// While connecting: why the bridge cannot use the broker now, in a sentence; null
    /// otherwise.
    pub problem: Option<String>,
}

written_schema!(
    /// A JSON Schema (2020-12) document of the contract, as published.
    JsonSchemaDocument,
    "json_schema",
    inline: false,
    json_schema!({
        "description": "A JSON Schema (2020-12) document of the contract, as published.",
        "type": "object",
        "required": ["$schema", "$id"]
    })
);

written_schema!(
    /// This document: OpenAPI 3.1, described by its own specification.
    OpenApiDocument,
    "openapi",
    inline: false,
    json_schema!({
        "description": "This document.",
        "type": "object",
        "required": ["openapi", "paths"]
    })
);
