//! `/api/v1/trials/{id}/picture`: what the robot's camera saw around the tag, sent once per
//! trial by the robot that made it and read by whoever may read the trial.

use axum::Json;
use axum::extract::{FromRequest, Request, State};
use axum::http::StatusCode;
use axum::http::header::{CACHE_CONTROL, CONTENT_TYPE, ETAG, X_CONTENT_TYPE_OPTIONS};
use axum::response::{IntoResponse, Response};
use bytes::Bytes;
use pps_schema::Epc;
use serde_json::json;

use crate::answers::trials::StoredTrialAnswer;
use crate::error::ApiError;
use crate::http::extract::{Caller, body_error};
use crate::http::ids::{InPath, TrialId};
use crate::http::openapi::doc::{Body, Doc, Header, Param, Reply};
use crate::http::precondition::IfNoneMatch;
use crate::state::AppState;
use crate::store::events::{self, EventKind};
use crate::store::pictures::StoredPicture;
use crate::store::{pictures, trials};
use crate::trials::picture::{Picture, PictureProblem, PictureType};

const MEDIA_TYPES: &[&str] = &["image/png", "image/jpeg"];
/// A stored picture never changes, so a browser may keep it a day; only a private cache, since
/// who may see it depends on the credential.
const CACHE: &str = "private, max-age=86400";

/// A request body sent as a picture type, not yet checked against its bytes.
#[derive(Debug)]
pub struct PictureBody(PictureType, Bytes);

impl<S: Send + Sync> FromRequest<S> for PictureBody {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, Self::Rejection> {
        let declared = req.headers().get(CONTENT_TYPE).and_then(|v| v.to_str().ok());
        let Some(kind) = declared.and_then(PictureType::from_content_type) else {
            return Err(ApiError::UnsupportedMediaType(
                "send the picture as `Content-Type: image/png` or `image/jpeg`".into(),
            ));
        };
        let bytes = Bytes::from_request(req, state).await.map_err(body_error)?;
        Ok(Self(kind, bytes))
    }
}

pub const PUT: Doc = Doc::new("putTrialPicture", "Send the picture of a trial, idempotently")
    .describe(
        "What the robot's camera saw around the tag, with its perception drawn in: a PNG or \
         JPEG of at most 256 KiB and 4096 pixels a side, whose bytes must be what its \
         Content-Type says. Only the robot that recorded the trial may send it, after the \
         trial. Sending the same bytes again is a no-op (200); other bytes for a trial that \
         has a picture are 409. The registry keeps the newest pictures of each tag (20 unless \
         configured otherwise); older ones are removed, their trials stay.",
    )
    .params(&[Param::TRIAL_ID])
    .body(Body::bytes(MEDIA_TYPES, "The picture's bytes"))
    .replies(&[
        Reply::json(200, "This very picture was stored before: the trial", "stored_trial"),
        Reply::json(201, "Stored: the trial, which now names its picture", "stored_trial"),
        Reply::problem(404, "No trial has this id: record the trial first"),
        Reply::problem(409, "The trial has another picture"),
        Reply::problem(413, "The picture is larger than 256 KiB"),
        Reply::problem(415, "Not sent as image/png or image/jpeg, or the bytes are another format"),
        Reply::problem(422, "The picture's header cannot be read, or it has too many pixels"),
    ]);

pub async fn put(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TrialId(id)): InPath<TrialId>,
    PictureBody(kind, bytes): PictureBody,
) -> Result<Response, ApiError> {
    let trial = trials::get(state.db.reader(), &id).await?.ok_or_else(|| {
        ApiError::NotFound(format!(
            "no trial has the id {id}; record the trial with PUT /api/v1/trials/{id} first"
        ))
    })?;
    if caller.robot.as_ref() != Some(&trial.robot) {
        return Err(ApiError::Forbidden(format!(
            "only the robot that recorded a trial sends its picture: the trial is {:?}'s, this \
             token is bound to {:?}",
            trial.robot.as_str(),
            caller.robot_name()
        )));
    }
    let picture = Picture::parse(kind, &bytes).map_err(problem)?;
    let mut tx = state.db.begin_write().await?;
    let now = state.clock.now();
    let stored = pictures::insert_new(&mut tx, &id, &picture, &bytes, now).await?;
    if !stored {
        let existing = pictures::describe(&mut tx, &id).await?;
        tx.commit().await?;
        return match existing {
            Some(existing) if existing.sha256 == picture.sha256 => {
                let row = trials::get(state.db.reader(), &id).await?.unwrap_or(trial);
                Ok((StatusCode::OK, Json(StoredTrialAnswer::from(&row))).into_response())
            }
            _ => Err(ApiError::Conflict(format!(
                "the trial {id} already has another picture; a trial keeps the first picture \
                 sent for it, and a retry must send exactly the same bytes"
            ))),
        };
    }
    let epc = trial.epc.as_hex();
    let removed = pictures::keep_newest(&mut tx, epc, state.pictures_per_tag, now).await?;
    let path = trials::picture_path(&id);
    events::append(
        &mut tx,
        EventKind::TrialUpdated,
        json!({ "trial": id, "epc": epc, "robot": trial.robot, "picture": path }),
    )
    .await?;
    tx.commit().await?;
    state.feed.committed();
    if removed > 0 {
        tracing::info!(
            epc,
            removed,
            keep = state.pictures_per_tag,
            "removed older pictures of a tag"
        );
    }
    let row = trials::get(state.db.reader(), &id).await?.unwrap_or(trial);
    Ok((StatusCode::CREATED, Json(StoredTrialAnswer::from(&row))).into_response())
}

fn problem(problem: PictureProblem) -> ApiError {
    let message = problem.to_string();
    match problem {
        PictureProblem::TooLarge(_) => ApiError::PayloadTooLarge(message),
        PictureProblem::WrongMagic(_) => ApiError::UnsupportedMediaType(message),
        PictureProblem::Unreadable(_) | PictureProblem::TooManyPixels(..) => {
            ApiError::invalid_at("", message)
        }
    }
}

pub const GET: Doc = Doc::new("getTrialPicture", "The picture of a trial")
    .describe(
        "The bytes the robot sent, as it sent them, with a strong ETag; If-None-Match with it \
         answers 304. Readable by whoever may read the trial.",
    )
    .params(&[Param::TRIAL_ID, Param::IF_NONE_MATCH_READ])
    .replies(&[
        Reply::bytes(200, "The picture", MEDIA_TYPES)
            .headers(&[Header::ETag, Header::CacheControlPrivate]),
        Reply::NOT_MODIFIED,
        Reply::problem(404, "No trial has this id, it has no picture, or retention removed it"),
    ]);

pub async fn get(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TrialId(id)): InPath<TrialId>,
    if_none_match: IfNoneMatch,
) -> Result<Response, ApiError> {
    super::trials::find_visible(&state, &caller, &id).await?;
    let stored = pictures::get(state.db.reader(), &id)
        .await?
        .ok_or_else(|| ApiError::NotFound(format!("the trial {id} has no picture")))?;
    let Some(bytes) = stored.bytes else {
        return Err(ApiError::NotFound(format!(
            "the picture of trial {id} was removed: the registry keeps only the newest \
             {} pictures of each tag",
            state.pictures_per_tag
        )));
    };
    Ok(send(stored.media_type, stored.sha256, bytes, CACHE, &if_none_match))
}

pub const TAG_GET: Doc = Doc::new("getTagPicture", "The newest picture of a tag")
    .describe(
        "What a robot saw the last time it sent a picture of this tag: the newest picture still          held of the tag's trials, with a strong ETag (If-None-Match answers 304). A tag list          shows it as the tag's thumbnail without reading the tag's trials. For caretakers and          admins; a robot reads the pictures of its own trials.",
    )
    .params(&[Param::EPC, Param::IF_NONE_MATCH_READ])
    .replies(&[
        Reply::bytes(200, "The picture", MEDIA_TYPES)
            .headers(&[Header::ETag, Header::CacheControlPrivate]),
        Reply::NOT_MODIFIED,
        Reply::problem(404, "No tag has this EPC, or no robot sent a picture of it that is kept"),
    ]);

pub async fn newest_of_tag(
    State(state): State<AppState>,
    InPath(epc): InPath<Epc>,
    if_none_match: IfNoneMatch,
) -> Result<Response, ApiError> {
    let stored = pictures::newest_of_tag(state.db.reader(), epc.as_hex()).await?;
    let Some(StoredPicture { media_type, sha256, bytes: Some(bytes) }) = stored else {
        return Err(ApiError::NotFound(format!(
            "no robot has sent a picture of the tag {epc} that is still kept"
        )));
    };
    // The newest picture changes as robots work: a browser asks again each time, and the ETag
    // makes that a 304 while nothing new arrived.
    Ok(send(media_type, sha256, bytes, "private, no-cache", &if_none_match))
}

/// A stored picture as an answer: its bytes under a strong ETag, or 304 when the caller has
/// them.
fn send(
    media_type: String,
    sha256: String,
    bytes: Vec<u8>,
    cache: &str,
    if_none_match: &IfNoneMatch,
) -> Response {
    let etag = format!("\"{sha256}\"");
    let headers = [
        (ETAG, etag.clone()),
        (CACHE_CONTROL, cache.to_owned()),
        (X_CONTENT_TYPE_OPTIONS, "nosniff".to_owned()),
    ];
    if if_none_match.names(&etag) {
        return (StatusCode::NOT_MODIFIED, headers).into_response();
    }
    (headers, [(CONTENT_TYPE, media_type)], bytes).into_response()
}
