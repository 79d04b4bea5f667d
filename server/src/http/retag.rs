//! `POST /api/v1/tags/{epc}/retag`: a worn tag replaced by a new one keeps its entry, history,
//! trials and learned values under the new EPC; the old EPC is remembered as retired.

use axum::Json;
use axum::extract::State;
use axum::http::HeaderMap;
use axum::http::header::ETAG;
use axum::response::{IntoResponse, Response};
use pps_schema::Epc;
use serde_json::json;

use crate::answers::contract;
use crate::answers::tags::StoredTagAnswer;
use crate::error::ApiError;
use crate::http::extract::{Caller, JsonBody};
use crate::http::ids::{InPath, Segment};
use crate::http::openapi::doc::{Body, Doc, Header, Param, Reply};
use crate::http::precondition;
use crate::state::AppState;
use crate::store::WriteCondition;
use crate::store::events::{self, EventKind};
use crate::store::{learning, retired, tags, tasks, trials};

/// The retag body: the new tag's EPC.
#[derive(Debug, serde::Deserialize, schemars::JsonSchema)]
#[schemars(rename = "retag")]
pub struct RetagBody {
    #[schemars(with = "contract::Epc")]
    pub new_epc: String,
}

pub const RETAG: Doc =
    Doc::new("retagTag", "Move an entry, its history and learned values to a new EPC")
        .describe("For a worn tag replaced by a new one; the old EPC is retired and never reused.")
        .params(&[Param::EPC, Param::IF_MATCH])
        .body(Body::json("retag", "The new tag's EPC"))
        .replies(&[
            Reply::json(200, "The entry under its new EPC", "stored_tag").headers(&[Header::ETag]),
            Reply::problem(404, "No tag has this EPC"),
            Reply::problem(409, "The new EPC belongs to another tag or was retired"),
            Reply::PRECONDITION_FAILED,
            Reply::INVALID,
        ]);

pub async fn retag(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(old): InPath<Epc>,
    headers: HeaderMap,
    JsonBody(body): JsonBody,
) -> Result<Response, ApiError> {
    let Ok(RetagBody { new_epc: new }) = serde_json::from_value(body) else {
        return Err(ApiError::invalid_at(
            "/new_epc",
            "say which EPC the new tag has: {\"new_epc\": \"E2...\"}",
        ));
    };
    let new =
        Epc::parse_segment(&new).map_err(|e| ApiError::invalid_at("/new_epc", e.to_string()))?;
    if new == old {
        return Err(ApiError::invalid_at("/new_epc", "the new EPC is the one the tag already has"));
    }
    let condition = precondition::write_condition(&headers)?.unwrap_or(WriteCondition::AnyRevision);
    let mut tx = state.db.begin_write().await?;
    let Some(current) = tags::current(&mut tx, &old).await? else {
        return Err(ApiError::NotFound(format!("no tag has the EPC {old}")));
    };
    if !condition.allows(current.revision) {
        return Err(ApiError::PreconditionFailed(format!(
            "the tag changed since you read it; it is now at revision {}",
            current.revision
        )));
    }
    if tags::current(&mut tx, &new).await?.is_some() {
        return Err(ApiError::Conflict(format!(
            "the EPC {new} already belongs to another tag; archive or retag that one first"
        )));
    }
    if retired::successor(&mut tx, &new).await?.is_some() {
        return Err(ApiError::Conflict(format!(
            "the EPC {new} was retired; a retired EPC is never reused"
        )));
    }
    let moved = tags::move_to(&mut tx, &current, &new, &caller.name).await?;
    let trials_moved = trials::move_to(&mut tx, &old, &new).await?;
    learning::move_to(&mut tx, &old, &new).await?;
    tasks::move_to(&mut tx, &old, &new).await?;
    retired::retire(&mut tx, &old, &new, &caller.name).await?;
    events::append(
        &mut tx,
        EventKind::TagRetagged,
        json!({ "epc": old.as_hex(), "new_epc": new.as_hex(), "trials": trials_moved }),
    )
    .await?;
    tx.commit().await?;
    state.effective.forget_tag(old.as_hex());
    state.effective.forget_tag(new.as_hex());
    state.feed.committed();
    Ok(([(ETAG, precondition::tag_etag(moved.revision))], Json(StoredTagAnswer::from(&moved)))
        .into_response())
}
