//! `GET /api/v1/openapi.json`: the OpenAPI 3.1 document of the API, generated from the route
//! table. Each route's [`Doc`] (written next to its handler) gives what only the handler knows;
//! its [`Access`] gives the security, the 401/403 answers and `x-roles`; the contract's JSON
//! Schemas are components as they are; the schemas of the registry's own answers and request
//! bodies are derived from the types that write and read them (`components`).
//!
//! This module only describes: it must never decide who may call a route or what it accepts.

pub(super) mod accounts;
mod components;
pub mod doc;

use std::sync::{Arc, OnceLock};

use axum::handler::Handler;
use axum::http::header::CONTENT_TYPE;
use axum::response::{IntoResponse, Response};
use bytes::Bytes;
use serde_json::{Map, Value, json};

use doc::{Body, Content, Doc, Param, ParamType, Reply};

use crate::error::ApiError;
use crate::http::{Access, RouteSpec};
use crate::identity::Role;
use crate::state::AppState;
use components::SCHEMAS;

pub const DOC: Doc =
    Doc::new("getOpenApi", "This document: the OpenAPI 3.1 description of the API")
        .replies(&[Reply::json(200, "The OpenAPI document", "openapi")]);

/// The document of one router, written once its table is complete and served from memory.
#[derive(Debug, Clone, Default)]
pub struct Published(Arc<OnceLock<Bytes>>);

impl Published {
    /// The handler of the document's own route, registered before the table is complete.
    pub fn handler(&self) -> impl Handler<((),), AppState> {
        let published = self.clone();
        move || std::future::ready(published.response())
    }

    pub fn publish(&self, routes: &[RouteSpec]) {
        // A JSON value always serializes.
        let text = serde_json::to_vec(&document(routes)).unwrap_or_default();
        // A router publishes once; a second call would describe the same table.
        let _ = self.0.set(Bytes::from(text));
    }

    fn response(&self) -> Response {
        match self.0.get() {
            Some(text) => ([(CONTENT_TYPE, "application/json")], text.clone()).into_response(),
            None => ApiError::Internal(anyhow::anyhow!("the OpenAPI document was never published"))
                .into_response(),
        }
    }
}

/// The OpenAPI document of `routes`.
pub fn document(routes: &[RouteSpec]) -> Value {
    let mut paths = Map::new();
    let schemas = components::schemas();
    for route in routes {
        let item = paths.entry(route.path).or_insert_with(|| json!({}));
        item[route.method.as_str().to_ascii_lowercase()] = operation(route);
    }
    json!({
        "openapi": "3.1.0",
        "jsonSchemaDialect": "https://json-schema.org/draft/2020-12/schema",
        "info": {
            "title": "PPS-tag registry",
            "version": env!("CARGO_PKG_VERSION"),
            "description": "Tag entries keyed by EPC with grounded semantics (what a thing is, \
                which actions it offers and how to do each), the robots' trials, per-robot \
                overrides, learned values and a change feed. Errors are RFC 9457 \
                application/problem+json; lists are pages of `{\"items\", \"next_cursor\"}`.",
            "license": { "name": "MIT OR Apache-2.0", "identifier": "MIT OR Apache-2.0" }
        },
        "paths": paths,
        "components": {
            "schemas": schemas,
            "securitySchemes": {
                "bearer": {
                    "type": "http",
                    "scheme": "bearer",
                    "description": "An API token (`pps_...`) from `pps-server token create` or \
                        POST /api/v1/tokens; a robot token is bound to one robot id."
                },
                "session": {
                    "type": "apiKey",
                    "in": "cookie",
                    "name": crate::auth::session::COOKIE_NAME,
                    "description": "The browser session from POST /api/v1/session; unsafe \
                        methods also need its csrf_token in the X-CSRF-Token header."
                }
            }
        }
    })
}

fn operation(route: &RouteSpec) -> Value {
    let doc = &route.doc;
    let mut operation = json!({
        "operationId": doc.operation_id,
        "summary": doc.summary,
        "description": description(doc, route.access),
        "tags": [resource(route.path)],
        "parameters": doc.params.iter().map(parameter).collect::<Vec<_>>(),
        "responses": responses(doc, route.access),
        "security": security(route.access),
        "x-access": access_name(route.access),
        "x-roles": roles(route.access),
    });
    if let Some(body) = &doc.body {
        operation["requestBody"] = request_body(body);
    }
    operation
}

fn description(doc: &Doc, access: Access) -> String {
    let who = match access {
        Access::Open => "Open: no credential needed.",
        Access::Anyone => "Any valid credential: admin, caretaker or robot.",
        Access::Editors => "Caretakers and admins.",
        Access::Admin => "Admins only.",
        Access::RobotOrEditors => "Caretakers, admins, and a robot for its own records only.",
        Access::Robot => "A robot, for its own records only.",
    };
    if doc.description.is_empty() {
        who.to_owned()
    } else {
        format!("{}\n\n{who}", doc.description)
    }
}

/// The first path segment after the API prefix groups operations for readers.
fn resource(path: &str) -> &str {
    let rest = path.strip_prefix("/api/v1/").unwrap_or(path.trim_start_matches('/'));
    rest.split(['/', '.']).next().unwrap_or(rest)
}

fn security(access: Access) -> Value {
    match access {
        Access::Open => json!([]),
        _ => json!([{ "bearer": [] }, { "session": [] }]),
    }
}

/// A stable name of the route's access rule, for tools that read the document.
pub fn access_name(access: Access) -> &'static str {
    match access {
        Access::Open => "open",
        Access::Anyone => "anyone",
        Access::Editors => "editors",
        Access::Admin => "admin",
        Access::RobotOrEditors => "robot-or-editors",
        Access::Robot => "robot",
    }
}

/// Who gets past the route's check: roles, and `anonymous` on open routes.
fn roles(access: Access) -> Vec<&'static str> {
    let anonymous = (access == Access::Open).then_some("anonymous");
    anonymous
        .into_iter()
        .chain(Role::ALL.into_iter().filter(|role| access.admits(*role)).map(Role::as_str))
        .collect()
}

fn parameter(param: &Param) -> Value {
    let mut parameter = json!({
        "name": param.name,
        "in": param.place.as_str(),
        "required": param.required(),
        "description": param.description,
        "schema": param_schema(param.value),
    });
    if let ParamType::SomeOf(_) = param.value {
        parameter["style"] = "form".into();
        parameter["explode"] = false.into();
    }
    if let Some(example) = param.example {
        parameter["example"] = example.into();
    }
    parameter
}

fn param_schema(value: ParamType) -> Value {
    match value {
        ParamType::Schema(name) => json!({ "$ref": format!("{SCHEMAS}{name}") }),
        ParamType::Text => json!({ "type": "string" }),
        ParamType::Boolean => json!({ "type": "boolean" }),
        ParamType::Integer { min, max } => {
            json!({ "type": "integer", "minimum": min, "maximum": max })
        }
        ParamType::Uuid => json!({ "type": "string", "format": "uuid" }),
        ParamType::DateTime => json!({ "type": "string", "format": "date-time" }),
        ParamType::OneOf(values) => json!({ "enum": values }),
        ParamType::SomeOf(values) => {
            json!({ "type": "array", "minItems": 1, "items": { "enum": values } })
        }
    }
}

fn request_body(body: &Body) -> Value {
    if !body.binary.is_empty() {
        let content: Map<String, Value> = body
            .binary
            .iter()
            .map(|media_type| ((*media_type).to_owned(), json!({ "schema": binary_schema() })))
            .collect();
        return json!({ "required": true, "description": body.description, "content": content });
    }
    let mut media = json!({ "schema": { "$ref": format!("{SCHEMAS}{}", body.schema) } });
    if let Some(example) = body.example.and_then(|text| serde_json::from_str::<Value>(text).ok()) {
        media["example"] = example;
    }
    let content: Map<String, Value> = std::iter::once("application/json")
        .chain(body.also.iter().copied())
        .map(|media_type| (media_type.to_owned(), media.clone()))
        .collect();
    json!({ "required": true, "description": body.description, "content": content })
}

/// Bytes of any kind, as OpenAPI 3.1 describes a file.
fn binary_schema() -> Value {
    json!({ "type": "string", "format": "binary" })
}

/// The route's own replies, then the ones every route of its kind gives.
fn responses(doc: &Doc, access: Access) -> Value {
    let mut replies: Vec<Reply> = doc.replies.to_vec();
    let mut common = |reply: Reply| {
        if !replies.iter().any(|r| r.status == reply.status) {
            replies.push(reply);
        }
    };
    if !doc.params.is_empty() || doc.body.is_some() {
        common(Reply::problem(400, "A parameter, header or body that cannot be read"));
    }
    if access != Access::Open {
        common(Reply::problem(401, "No credential, or one that is unknown, revoked or expired"));
        common(Reply::problem(
            403,
            "The credential's role may not do this (or a browser request lacks its anti-forgery \
             token)",
        ));
    }
    if doc.body.is_some() {
        common(Reply::problem(413, "The body is larger than 1 MiB"));
        common(Reply::problem(415, "The body is not sent as application/json"));
    }
    replies.sort_by_key(|reply| reply.status);
    let responses: Map<String, Value> =
        replies.iter().map(|reply| (reply.status.to_string(), response(reply))).collect();
    Value::Object(responses)
}

fn response(reply: &Reply) -> Value {
    let mut response = json!({ "description": reply.description });
    let content = match reply.content {
        Content::Json(name) => {
            Some(("application/json", json!({ "$ref": format!("{SCHEMAS}{name}") })))
        }
        Content::Page(item) => {
            Some(("application/json", json!({ "$ref": format!("{SCHEMAS}{item}_page") })))
        }
        Content::Problem => {
            Some(("application/problem+json", json!({ "$ref": format!("{SCHEMAS}problem") })))
        }
        Content::Text => Some(("text/plain", json!({ "type": "string" }))),
        Content::EventStream => Some((
            "text/event-stream",
            json!({
                "type": "string",
                "description": "Server-Sent Events: `id` (monotonic, for Last-Event-ID), \
                    `event` (the kind of change) and `data` (JSON naming the thing changed)"
            }),
        )),
        Content::Bytes(media_types) => {
            let content: Map<String, Value> = media_types
                .iter()
                .map(|media_type| ((*media_type).to_owned(), json!({ "schema": binary_schema() })))
                .collect();
            response["content"] = Value::Object(content);
            None
        }
        Content::Empty => None,
    };
    if let Some((media_type, schema)) = content {
        response["content"] = json!({ media_type: { "schema": schema } });
    }
    if !reply.headers.is_empty() {
        let headers: Map<String, Value> = reply
            .headers
            .iter()
            .map(|header| {
                let spec = json!({
                    "description": header.description(),
                    "schema": { "type": "string" }
                });
                (header.name().to_owned(), spec)
            })
            .collect();
        response["headers"] = Value::Object(headers);
    }
    response
}
