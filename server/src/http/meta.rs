//! Open routes about the registry itself: liveness and the JSON Schemas.

use axum::Json;
use axum::extract::Path;
use serde_json::{Value, json};

use crate::error::ApiError;

pub async fn healthz() -> Json<Value> {
    Json(json!({ "status": "ok" }))
}

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

pub async fn metrics(
    axum::extract::State(state): axum::extract::State<crate::state::AppState>,
) -> impl axum::response::IntoResponse {
    (
        [(axum::http::header::CONTENT_TYPE, "text/plain; version=0.0.4; charset=utf-8")],
        state.metrics.render(state.feed.clients()),
    )
}
