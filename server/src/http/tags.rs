//! `/api/v1/tags`: list, read, create or replace, archive and restore, history, validation.

use axum::Json;
use axum::extract::State;
use axum::http::header::{ETAG, LOCATION};
use axum::http::{HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use serde::Deserialize;
use serde_json::{Value, json};

use crate::entry;
use crate::error::ApiError;
use crate::http::extract::{ApiQuery, Caller, EpcPath, JsonBody};
use crate::http::page::{self, Page, PageParams};
use crate::http::precondition::{self, WriteCondition};
use crate::state::AppState;
use crate::store::tags::{self, StoredTag, TagFilter, TagWriteError};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ListParams {
    #[serde(rename = "type")]
    kind: Option<String>,
    q: Option<String>,
    #[serde(default)]
    archived: bool,
    limit: Option<u32>,
    cursor: Option<String>,
}

pub async fn list(
    State(state): State<AppState>,
    ApiQuery(params): ApiQuery<ListParams>,
) -> Result<Json<Page<Value>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = params.cursor.as_deref().map(page::decode_cursor).transpose()?;
    let filter = TagFilter {
        kind: params.kind.filter(|k| !k.is_empty()),
        name_contains: params.q.filter(|q| !q.is_empty()),
        archived: params.archived,
    };
    let rows = tags::list(state.db.reader(), &filter, after.as_deref(), limit + 1).await?;
    let page = page::page(rows, limit, |tag| tag.epc.clone());
    Ok(Json(Page {
        items: page.items.iter().map(StoredTag::to_json).collect(),
        next_cursor: page.next_cursor,
    }))
}

pub async fn get(
    State(state): State<AppState>,
    EpcPath(epc): EpcPath,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    let tag = tags::get(state.db.reader(), &epc).await?.ok_or_else(|| not_found(&epc))?;
    let etag = precondition::tag_etag(tag.revision);
    if precondition::not_modified(&headers, &etag) {
        return Ok((StatusCode::NOT_MODIFIED, [(ETAG, etag)]).into_response());
    }
    Ok(with_etag(StatusCode::OK, &tag))
}

pub async fn put(
    State(state): State<AppState>,
    Caller(caller): Caller,
    EpcPath(epc): EpcPath,
    headers: HeaderMap,
    JsonBody(body): JsonBody,
) -> Result<Response, ApiError> {
    let condition = precondition::write_condition(&headers)?.ok_or_else(|| {
        ApiError::PreconditionRequired(
            "say what you expect: `If-None-Match: *` to create a new tag, or `If-Match` with \
             the ETag from your last GET to replace one"
                .into(),
        )
    })?;
    let (epc, entry) = entry::accept(Some(&epc), body)?;
    let written = tags::put(&state.db, &epc, &entry, &condition, &caller.name).await;
    if written.is_ok() {
        changed(&state, &epc);
    }
    match written {
        Ok((tag, true)) => {
            let mut response = with_etag(StatusCode::CREATED, &tag);
            if let Ok(location) = HeaderValue::from_str(&format!("/api/v1/tags/{}", tag.epc)) {
                response.headers_mut().insert(LOCATION, location);
            }
            Ok(response)
        }
        Ok((tag, false)) => Ok(with_etag(StatusCode::OK, &tag)),
        Err(error) => Err(write_error(&epc, &condition, error)),
    }
}

pub async fn archive(
    State(state): State<AppState>,
    Caller(caller): Caller,
    EpcPath(epc): EpcPath,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    let condition = match precondition::write_condition(&headers)? {
        Some(condition @ (WriteCondition::AnyRevision | WriteCondition::Revisions(_))) => condition,
        _ => {
            return Err(ApiError::PreconditionRequired(
                "archiving needs `If-Match` with the ETag from your last GET, so you archive \
                 the entry you saw"
                    .into(),
            ));
        }
    };
    match tags::archive(&state.db, &epc, &condition, &caller.name).await {
        Ok(tag) => {
            changed(&state, &epc);
            Ok(with_etag(StatusCode::OK, &tag))
        }
        Err(error) => Err(write_error(&epc, &condition, error)),
    }
}

pub async fn revisions(
    State(state): State<AppState>,
    EpcPath(epc): EpcPath,
    ApiQuery(params): ApiQuery<PageParams>,
) -> Result<Json<Page<tags::Revision>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = match params.cursor.as_deref().map(page::decode_cursor).transpose()? {
        Some(text) => text.parse().map_err(|_| ApiError::BadRequest("malformed cursor".into()))?,
        None => 0,
    };
    let rows = tags::revisions(state.db.reader(), &epc, after, limit + 1).await?;
    if rows.is_empty() && after == 0 {
        return Err(not_found(&epc));
    }
    Ok(Json(page::page(rows, limit, |revision| revision.revision.to_string())))
}

pub async fn validate(JsonBody(body): JsonBody) -> Result<Json<Value>, ApiError> {
    entry::accept(None, body)?;
    Ok(Json(json!({ "valid": true, "errors": [] })))
}

/// After a committed change: robots must see it on their next read, and the feed must tell.
fn changed(state: &AppState, epc: &pps_schema::Epc) {
    state.effective.forget_tag(epc.as_hex());
    state.feed.committed();
}

fn with_etag(status: StatusCode, tag: &StoredTag) -> Response {
    let etag = precondition::tag_etag(tag.revision);
    (status, [(ETAG, etag)], Json(tag.to_json())).into_response()
}

fn not_found(epc: &pps_schema::Epc) -> ApiError {
    ApiError::NotFound(format!("no tag has the EPC {epc}; register it with PUT /api/v1/tags/{epc}"))
}

fn write_error(
    epc: &pps_schema::Epc,
    condition: &WriteCondition,
    error: TagWriteError,
) -> ApiError {
    match error {
        TagWriteError::Exists { current } => ApiError::PreconditionFailed(format!(
            "a tag with the EPC {epc} already exists (revision {}{}); GET it and replace it with \
             If-Match instead",
            current.revision,
            if current.archived { ", archived" } else { "" }
        )),
        TagWriteError::Missing if *condition == WriteCondition::Absent => not_found(epc),
        TagWriteError::Missing => ApiError::PreconditionFailed(format!(
            "no tag has the EPC {epc}, so If-Match cannot hold; create it with If-None-Match: *"
        )),
        TagWriteError::Stale { current } => ApiError::PreconditionFailed(format!(
            "someone changed this tag since you read it: it is now at revision {} (ETag {}), \
             saved by {} at {}; GET it again and reapply your change",
            current.revision,
            precondition::tag_etag(current.revision),
            current.updated_by,
            current.updated_at
        )),
        TagWriteError::Database(error) => error.into(),
    }
}
