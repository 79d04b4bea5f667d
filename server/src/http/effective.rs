//! `GET /api/v1/robots/{robot}/tags/{epc}`: the robots' hot path, right after an RFID read.
//!
//! Served from memory when it can be; a miss reads the database once and caches the result.
//! A read never writes: an unknown EPC is noted for the inbox in memory.

use axum::body::Body;
use axum::extract::State;
use axum::http::header::{CONTENT_TYPE, ETAG};
use axum::http::{HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use pps_schema::{Epc, RobotId};

use crate::effective_entry::entry_for;
use crate::error::ApiError;
use crate::http::extract::Caller;
use crate::http::ids::InPath;
use crate::http::openapi::doc::{Doc, Header, Param, Reply};
use crate::http::precondition;
use crate::state::AppState;

pub const GET: Doc = Doc::new("getEffectiveEntry", "The entry as this robot should use it")
    .describe(
        "Base entry, learned values, class and robot overrides merged (later wins), the source \
         of every leaf, and the actions this robot cannot run with the reason. An unknown EPC \
         is noted in the inbox.",
    )
    .params(&[Param::ROBOT, Param::EPC, Param::IF_NONE_MATCH_READ])
    .replies(&[
        Reply::json(200, "The effective entry", "effective_entry").headers(&[Header::ETag]),
        Reply::NOT_MODIFIED,
        Reply::problem(404, "No active tag has this EPC (it is unknown, archived or retired)"),
    ]);

pub async fn get(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath((robot, epc)): InPath<(RobotId, Epc)>,
    if_none_match: precondition::IfNoneMatch,
) -> Result<Response, ApiError> {
    caller.require_robot_or_editor(&robot)?;
    let entry = entry_for(&state, &epc, &robot).await?;
    if if_none_match.names(entry.etag.to_str().unwrap_or_default()) {
        return Ok((StatusCode::NOT_MODIFIED, [(ETAG, entry.etag.clone())]).into_response());
    }
    let mut response = Response::new(Body::from(entry.body.clone()));
    let headers = response.headers_mut();
    headers.insert(CONTENT_TYPE, HeaderValue::from_static("application/json"));
    headers.insert(ETAG, entry.etag.clone());
    Ok(response)
}
