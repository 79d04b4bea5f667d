//! `/api/v1/tags`: list, read, create or replace, archive and restore, history, validation.

use crate::accept::accept;
use crate::answers::tags::{StoredTagAnswer, TagRevisionAnswer, ValidationResult};
use crate::error::ApiError;
use crate::http::extract::{ApiQuery, Caller, JsonBody};
use crate::http::ids::InPath;
use crate::http::openapi::doc::{Body, Doc, Header, Param, ParamType, Reply};
use crate::http::page::{self, Page, PageParams};
use crate::http::precondition;
use crate::state::AppState;
use crate::store::WriteCondition;
use crate::store::tags::{self, StoredTag, TagFilter, TagWriteError};
use axum::Json;
use axum::extract::State;
use axum::http::header::{ETAG, LOCATION};
use axum::http::{HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use pps_schema::{Epc, TagEntry};
use serde::Deserialize;

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

pub const LIST: Doc = Doc::new("listTags", "List tags, by EPC")
    .params(&[
        Param::query("type", ParamType::Text, "Only tags whose properties.type is this"),
        Param::query("q", ParamType::Text, "Only tags whose name contains this text"),
        Param::query("archived", ParamType::Boolean, "List archived tags instead of active ones"),
        Param::LIMIT,
        Param::CURSOR,
    ])
    .replies(&[Reply::page("A page of stored entries, ordered by EPC", "stored_tag")]);

pub async fn list(
    State(state): State<AppState>,
    ApiQuery(params): ApiQuery<ListParams>,
) -> Result<Json<Page<StoredTagAnswer>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = params.cursor.as_deref().map(page::decode_cursor).transpose()?;
    let filter = TagFilter {
        kind: params.kind.filter(|k| !k.is_empty()),
        name_contains: params.q.filter(|q| !q.is_empty()),
        archived: params.archived,
    };
    let rows = tags::list(state.db.reader(), &filter, after.as_deref(), limit + 1).await?;
    let page = page::page(rows, limit, |tag| tag.epc.as_hex().to_owned());
    Ok(Json(page.map(|tag| StoredTagAnswer::from(&tag))))
}

pub const GET: Doc = Doc::new("getTag", "One stored entry with its read-only fields")
    .params(&[Param::EPC, Param::IF_NONE_MATCH_READ])
    .replies(&[
        Reply::json(200, "The entry", "stored_tag").headers(&[Header::ETag]),
        Reply::NOT_MODIFIED,
        Reply::problem(404, "No tag has this EPC"),
    ]);

pub async fn get(
    State(state): State<AppState>,
    InPath(epc): InPath<Epc>,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    let tag = tags::get(state.db.reader(), &epc).await?.ok_or_else(|| not_found(&epc))?;
    let etag = precondition::tag_etag(tag.revision);
    if precondition::not_modified(&headers, &etag)? {
        return Ok((StatusCode::NOT_MODIFIED, [(ETAG, etag)]).into_response());
    }
    Ok(with_etag(StatusCode::OK, &tag))
}

pub const PUT: Doc = Doc::new("putTag", "Create or replace a tag entry")
    .describe(
        "Create with `If-None-Match: *`; replace (or restore an archived entry) with `If-Match` \
         and the ETag of the revision the change is based on. Read-only fields are ignored, so \
         GET, edit, PUT round-trips. Every problem of the entry is listed at once.",
    )
    .params(&[Param::EPC, Param::IF_MATCH, Param::IF_NONE_MATCH_CREATE])
    .body(
        Body::json("tag", "The entry; its epc must be the one in the path")
            .example(include_str!("../../../seed_tags/ada_light_switch.json")),
    )
    .replies(&[
        Reply::json(200, "Replaced", "stored_tag").headers(&[Header::ETag]),
        Reply::json(201, "Created", "stored_tag").headers(&[Header::ETag, Header::Location]),
        Reply::problem(409, "The EPC was retired when its tag was replaced and is never reused"),
        Reply::PRECONDITION_FAILED,
        Reply::INVALID,
        Reply::PRECONDITION_REQUIRED,
    ]);

pub async fn put(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(epc): InPath<Epc>,
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
    let (epc, entry) = accept::<TagEntry>(Some(&epc), body)?;
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

pub const ARCHIVE: Doc = Doc::new("archiveTag", "Archive a tag; its trials are kept")
    .describe("A PUT with the archived revision's ETag restores it.")
    .params(&[Param::EPC, Param::IF_MATCH])
    .replies(&[
        Reply::json(200, "The archived entry", "stored_tag").headers(&[Header::ETag]),
        Reply::PRECONDITION_FAILED,
        Reply::PRECONDITION_REQUIRED,
    ]);

pub async fn archive(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(epc): InPath<Epc>,
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

pub const REVISIONS: Doc =
    Doc::new("listTagRevisions", "Every change of a tag: who, when, the entry")
        .params(&[Param::EPC, Param::LIMIT, Param::CURSOR])
        .replies(&[
            Reply::page("A page of revisions, oldest first", "tag_revision"),
            Reply::problem(404, "No tag has this EPC"),
        ]);

pub async fn revisions(
    State(state): State<AppState>,
    InPath(epc): InPath<Epc>,
    ApiQuery(params): ApiQuery<PageParams>,
) -> Result<Json<Page<TagRevisionAnswer>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = page::decode_position(params.cursor.as_deref())?;
    let rows = tags::revisions(state.db.reader(), &epc, after, limit + 1).await?;
    if rows.is_empty() && after == 0 {
        return Err(not_found(&epc));
    }
    let page = page::page(rows, limit, |revision| revision.revision.to_string());
    Ok(Json(page.map(TagRevisionAnswer::from)))
}

pub const VALIDATE: Doc = Doc::new("validateTag", "Validate an entry without storing it")
    .body(
        Body::json("tag", "The entry to check")
            .example(include_str!("../../../seed_tags/lamp.json")),
    )
    .replies(&[Reply::json(200, "The entry is valid", "validation_result"), Reply::INVALID]);

pub async fn validate(JsonBody(body): JsonBody) -> Result<Json<ValidationResult>, ApiError> {
    accept::<TagEntry>(None, body)?;
    Ok(Json(ValidationResult::VALID))
}

/// After a committed change: robots must see it on their next read, and the feed must tell.
fn changed(state: &AppState, epc: &pps_schema::Epc) {
    state.effective.forget_tag(epc.as_hex());
    state.feed.committed();
}

fn with_etag(status: StatusCode, tag: &StoredTag) -> Response {
    let etag = precondition::tag_etag(tag.revision);
    (status, [(ETAG, etag)], Json(StoredTagAnswer::from(tag))).into_response()
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
            crate::clock::format(current.updated_at)
        )),
        TagWriteError::Retired { successor } => ApiError::Conflict(format!(
            "the EPC {epc} was retired when its worn tag was replaced by {successor}; a retired \
             EPC is never used again, so give the new tag its own EPC"
        )),
        TagWriteError::Database(error) => error.into(),
    }
}
