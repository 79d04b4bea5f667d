//! Open routes about the registry itself: liveness and the JSON Schemas.

use axum::Json;
use axum::extract::Path;
use serde_json::Value;

use crate::answers::meta::Health;
use crate::error::ApiError;
use crate::http::openapi::doc::{Doc, Param, ParamType, Reply};

pub const HEALTHZ: Doc = Doc::new("healthz", "Liveness: the registry answers")
    .replies(&[Reply::json(200, "Alive", "health")]);

pub async fn healthz() -> Json<Health> {
    Json(Health::OK)
}

pub const READYZ: Doc = Doc::new("readyz", "Readiness: the registry can store writes now")
    .describe(
        "200 while there is room on the database's disk and its write lock can be taken; 503 \
         (with Retry-After and the reason) while writes would be refused, e.g. on a full disk. \
         Writes resume by themselves once the cause is gone.",
    )
    .replies(&[
        Reply::json(200, "Ready to take writes", "health"),
        Reply::problem(503, "Writes would be refused now; the detail says why"),
    ]);

pub async fn readyz(
    axum::extract::State(state): axum::extract::State<crate::state::AppState>,
) -> Result<Json<Health>, ApiError> {
    state.db.readiness().await.map_err(|why| ApiError::Unavailable(why.to_string()))?;
    Ok(Json(Health::OK))
}

pub const SCHEMA: Doc = Doc::new("getSchema", "One JSON Schema of the contract, as published")
    .params(&[Param::path(
        "name",
        ParamType::OneOf(pps_schema::SCHEMA_NAMES),
        "The schema's name (`.json` and `.schema.json` suffixes are accepted too)",
    )
    .example("tag")])
    .replies(&[
        Reply::json(200, "The JSON Schema (2020-12) document", "json_schema"),
        Reply::problem(404, "There is no schema of this name"),
    ]);

pub async fn schema(Path(name): Path<String>) -> Result<Json<Value>, ApiError> {
    let name =
        name.strip_suffix(".schema.json").or_else(|| name.strip_suffix(".json")).unwrap_or(&name);
    pps_schema::schema_document(name).cloned().map(Json).ok_or_else(|| {
        ApiError::NotFound(format!(
            "there is no schema named {name:?}; the schemas are {}",
            pps_schema::SCHEMA_NAMES.join(", ")
        ))
    })
}

pub const METRICS: Doc =
    Doc::new("metrics", "Request counts and latencies, in Prometheus text format")
        .replies(&[Reply::text(200, "The metrics")]);

pub async fn metrics(
    axum::extract::State(state): axum::extract::State<crate::state::AppState>,
) -> impl axum::response::IntoResponse {
    let mut text = state.metrics.render(state.feed.clients());
    text.push_str(&format!(
        "# HELP pps_robots_waiting_for_tasks Robots whose claim is waiting for a task.\n\
         # TYPE pps_robots_waiting_for_tasks gauge\npps_robots_waiting_for_tasks {}\n\
         # HELP pps_task_looks_total Times a claim read the queue for a task.\n\
         # TYPE pps_task_looks_total counter\npps_task_looks_total {}\n",
        state.tasks.waiting(),
        state.tasks.looks()
    ));
    text.push_str(&format!(
        "# HELP pps_heavy_answers_building Answers of megabytes being built now.\n\
         # TYPE pps_heavy_answers_building gauge\npps_heavy_answers_building {}\n\
         # HELP pps_heavy_answers_waiting Requests waiting for their address's turn to build one.\n\
         # TYPE pps_heavy_answers_waiting gauge\npps_heavy_answers_waiting {}\n",
        state.heavy_answers.building(),
        state.heavy_answers.waiting()
    ));
    ([(axum::http::header::CONTENT_TYPE, "text/plain; version=0.0.4; charset=utf-8")], text)
}
