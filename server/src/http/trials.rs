//! `/api/v1/trials`: what robots did, written by them once per attempt (idempotently, by a
//! UUID they choose) and read by caretakers, the UI and learning.

use std::net::{IpAddr, SocketAddr};

use axum::extract::{ConnectInfo, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::{Extension, Json};
use pps_schema::{MAX_FORCE_SAMPLES, Purpose, Trial};
use serde::Deserialize;
use serde_json::{Value, json};
use uuid::Uuid;

use crate::accept::accept;
use crate::answers::trials::StoredTrialAnswer;
use crate::auth::Principal;
use crate::error::ApiError;
use crate::http::extract::{ApiQuery, Caller, JsonBody};
use crate::http::ids::{InPath, TrialId};
use crate::http::openapi::doc::{Body, Doc, Param, ParamType, Reply};
use crate::http::page::{self, Page};
use crate::identity::Role;
use crate::learning::{self, TrialGroup};
use crate::state::AppState;
use crate::store::events::{self, EventKind};
use crate::store::trials::{self, TrialRow};
use crate::trial_history::writer::{CheckedTrial, Recorded, TrialRejection};
use crate::trials::filter::{FilterText, TrialFilter};

/// A trial of robot `el-e-1` on the seeded ADA switch, under the id of [`Param::TRIAL_ID`]'s
/// example.
const EXAMPLE_TRIAL: &str = r#"{
    "id": "0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10", "epc": "355AB1C60000002000000001",
    "robot": "el-e-1", "action": "on", "behavior": "push_top", "outcome": "success",
    "started_at": "2026-11-22T10:00:00Z", "finished_at": "2026-11-22T10:00:30Z",
    "detector": { "brightness_change": 0.4 }, "forces": [], "measurements": {}
}"#;

pub const PUT: Doc = Doc::new("putTrial", "Record a trial, idempotently")
    .describe(
        "The robot chooses the UUID; sending the same trial again is a no-op (200), another \
         body under the same id is 409. The robot may only record its own trials.",
    )
    .params(&[Param::TRIAL_ID])
    .body(
        Body::json("trial", "The trial; its id, when given, must be the one in the path")
            .example(EXAMPLE_TRIAL),
    )
    .replies(&[
        Reply::json(200, "Already recorded with this very body", "stored_trial"),
        Reply::json(201, "Recorded", "stored_trial"),
        Reply::problem(409, "Another trial is stored under this id"),
        Reply::problem(413, "More force samples than a trial may carry"),
        Reply::INVALID,
        Reply::problem(503, "The registry is shutting down; retry"),
    ]);

pub async fn put(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TrialId(id)): InPath<TrialId>,
    JsonBody(body): JsonBody,
) -> Result<Response, ApiError> {
    let samples = body.get("forces").and_then(Value::as_array).map_or(0, Vec::len);
    if samples > MAX_FORCE_SAMPLES {
        return Err(ApiError::PayloadTooLarge(format!(
            "a trial carries at most {MAX_FORCE_SAMPLES} force samples; this one has {samples}: \
             downsample them or keep a summary in measurements"
        )));
    }
    let (_, mut body) = accept::<Trial>(Some(&id), body)?;
    // Real use goes without saying, as it did before trials had a purpose: a trial recorded
    // then and retried now, or retried with the default spelled out, is the same trial.
    if body.get("purpose").and_then(Value::as_str) == Some(Purpose::Use.as_str()) {
        pps_schema::strip_fields(&mut body, &["purpose"]);
    }
    let trial: Trial = serde_json::from_value(body.clone()).map_err(|error| {
        ApiError::invalid_at("", format!("the trial does not fit its type: {error}"))
    })?;
    if caller.robot.as_ref() != Some(&trial.robot) {
        return Err(ApiError::Forbidden(format!(
            "a robot records only its own trials: this token is bound to {:?}, the trial names {:?}",
            caller.robot_name(),
            trial.robot.as_str()
        )));
    }
    let epc = trial.epc.clone();
    let checked = CheckedTrial { trial, body };
    match state.trials.record(checked).await {
        Ok(Recorded::New(row)) => {
            state.metrics.trial_recorded();
            Ok((StatusCode::CREATED, Json(StoredTrialAnswer::from(&row))).into_response())
        }
        Ok(Recorded::Repeat(row)) => {
            Ok((StatusCode::OK, Json(StoredTrialAnswer::from(&row))).into_response())
        }
        Err(rejection) => Err(rejection_error(&epc, rejection)),
    }
}

fn rejection_error(epc: &pps_schema::Epc, rejection: TrialRejection) -> ApiError {
    match rejection {
        TrialRejection::Conflict(existing) => ApiError::Conflict(format!(
            "another trial is already stored under this id (received {}); a retry must send \
             exactly the same body, and a new attempt needs a new UUID",
            crate::clock::format(existing.received_at)
        )),
        TrialRejection::UnknownTag => ApiError::invalid_at(
            "/epc",
            format!("no tag has the EPC {epc}; register the tag before recording trials on it"),
        ),
        TrialRejection::ArchivedTag => ApiError::invalid_at(
            "/epc",
            format!("the tag {epc} is archived; restore it to record trials on it"),
        ),
        TrialRejection::RetiredTag(successor) => ApiError::invalid_at(
            "/epc",
            format!(
                "the EPC {epc} was retired when its tag was replaced; record the trial on {successor}"
            ),
        ),
        TrialRejection::Database(error) => ApiError::unwritable(&error)
            .unwrap_or_else(|| ApiError::Internal(anyhow::anyhow!("storing a trial: {error}"))),
        TrialRejection::ShuttingDown => {
            ApiError::Unavailable("the registry is shutting down; retry in a moment".into())
        }
    }
}

pub const GET: Doc = Doc::new("getTrial", "One trial").params(&[Param::TRIAL_ID]).replies(&[
    Reply::json(200, "The trial", "stored_trial"),
    Reply::problem(404, "No trial has this id"),
]);

pub async fn get(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TrialId(id)): InPath<TrialId>,
) -> Result<Json<StoredTrialAnswer>, ApiError> {
    let row = find_visible(&state, &caller, &id).await?;
    Ok(Json(StoredTrialAnswer::from(&row)))
}

/// A trial the caller may see: a robot sees only its own.
pub(super) async fn find_visible(
    state: &AppState,
    caller: &Principal,
    id: &Uuid,
) -> Result<TrialRow, ApiError> {
    let row = trials::get(state.db.reader(), id)
        .await?
        .ok_or_else(|| ApiError::NotFound(format!("no trial has the id {id}")))?;
    caller.require_robot_or_editor(&row.robot)?;
    Ok(row)
}

/// A merge patch of a trial: only the person's verdict may change.
#[derive(Debug, schemars::JsonSchema)]
#[schemars(rename = "verdict")]
pub struct VerdictPatch {
    /// The person's verdict: true (it worked), false (it did not) or null (no verdict);
    /// left out, the verdict stays as it is.
    #[schemars(with = "Option<bool>")]
    pub confirmed: Option<Option<bool>>,
}

impl VerdictPatch {
    /// Reads a merge patch, every problem reported at once.
    fn parse(body: &Value) -> Result<Self, ApiError> {
        let Some(patch) = body.as_object() else {
            return Err(ApiError::invalid_at(
                "",
                "a merge patch is a JSON object, e.g. {\"confirmed\": true}",
            ));
        };
        let mut errors = Vec::new();
        for key in patch.keys().filter(|key| *key != "confirmed") {
            errors.push(pps_schema::FieldError::new(
                pps_schema::pointer::join("", key),
                format!("{key} cannot be changed after the trial is recorded; only confirmed (the person's verdict) can"),
            ));
        }
        let confirmed = match patch.get("confirmed") {
            None => None,
            Some(Value::Bool(verdict)) => Some(Some(*verdict)),
            Some(Value::Null) => Some(None),
            Some(_) => {
                errors.push(pps_schema::FieldError::new(
                    "/confirmed",
                    "confirmed is true, false or null",
                ));
                None
            }
        };
        if errors.is_empty() { Ok(Self { confirmed }) } else { Err(ApiError::Invalid(errors)) }
    }
}

pub const PATCH: Doc = Doc::new("confirmTrial", "Set the person's verdict on a trial")
    .params(&[Param::TRIAL_ID])
    .body(
        Body::json("verdict", "A merge patch holding only `confirmed`")
            .also(&["application/merge-patch+json"])
            .example(r#"{ "confirmed": true }"#),
    )
    .replies(&[
        Reply::json(200, "The trial with its verdict", "stored_trial"),
        Reply::problem(404, "No trial has this id"),
        Reply::INVALID,
    ]);

pub async fn patch(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TrialId(id)): InPath<TrialId>,
    JsonBody(body): JsonBody,
) -> Result<Json<StoredTrialAnswer>, ApiError> {
    let row = find_visible(&state, &caller, &id).await?;
    let confirmed = VerdictPatch::parse(&body)?.confirmed.unwrap_or(row.confirmed);
    if confirmed == row.confirmed {
        return Ok(Json(StoredTrialAnswer::from(&row)));
    }
    let mut tx = state.db.begin_write().await?;
    trials::set_confirmed(&mut tx, &id, confirmed).await?;
    events::append(
        &mut tx,
        EventKind::TrialUpdated,
        json!({ "trial": row.id, "epc": row.epc, "robot": row.robot, "confirmed": confirmed }),
    )
    .await?;
    let behavior =
        row.submitted().get("behavior").and_then(Value::as_str).unwrap_or_default().to_owned();
    let group = TrialGroup {
        epc: row.epc.clone(),
        action: row.action.clone(),
        behavior,
        robot_class: row.robot_class.clone(),
        relearn: true,
    };
    let relearned = learning::update(&mut tx, &[group].into()).await?;
    tx.commit().await?;
    for epc in relearned {
        state.effective.forget_tag(epc.as_hex());
    }
    state.feed.committed();
    Ok(Json(StoredTrialAnswer::from(&TrialRow { confirmed, ..row })))
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ListParams {
    epc: Option<String>,
    robot: Option<String>,
    action: Option<String>,
    outcome: Option<String>,
    since: Option<String>,
    purpose: Option<String>,
    include: Option<String>,
    limit: Option<u32>,
    cursor: Option<String>,
}

/// Stored trial bytes one page of the list holds at most: a page ends early (with a cursor)
/// rather than make the registry hold hundreds of megabytes of force samples for one answer.
pub const MAX_PAGE_BYTES: usize = 4 << 20;

pub const LIST: Doc = Doc::new("listTrials", "Trial history, oldest first")
    .describe(
        "A robot lists only its own trials. Force samples are left out unless \
         `include=forces`; a page also ends early (with next_cursor) once it holds 4 MiB of \
         trials, so it may have fewer than `limit` items although more follow.",
    )
    .params(&[
        Param::query("epc", ParamType::Schema("tag/$defs/epc"), "Only trials on this tag"),
        Param::query("robot", ParamType::Schema("robot/$defs/robot_id"), "Only this robot's"),
        Param::query("action", ParamType::Text, "Only this action"),
        Param::query(
            "outcome",
            ParamType::OneOf(&["success", "failure", "aborted", "error"]),
            "Only this outcome",
        ),
        Param::query("since", ParamType::DateTime, "Only trials started at or after this time"),
        Param::query(
            "purpose",
            ParamType::OneOf(&["use", "experiment", "test"]),
            "Only trials made for this purpose: real use, an experiment or a test",
        ),
        Param::query(
            "include",
            ParamType::OneOf(&["forces"]),
            "`forces`: each trial with its force samples",
        ),
        Param::LIMIT,
        Param::CURSOR,
    ])
    .replies(&[Reply::page("A page of trials", "stored_trial")]);

pub async fn list(
    State(state): State<AppState>,
    Caller(caller): Caller,
    client: Option<Extension<ConnectInfo<SocketAddr>>>,
    ApiQuery(params): ApiQuery<ListParams>,
) -> Result<Response, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = page::decode_position(params.cursor.as_deref())?;
    let mut filter = TrialFilter::parse(FilterText {
        epc: params.epc.as_deref(),
        robot: params.robot.as_deref(),
        action: params.action.as_deref(),
        outcome: params.outcome.as_deref(),
        since: params.since.as_deref(),
        purpose: params.purpose.as_deref(),
    })
    .map_err(|error| ApiError::BadRequest(error.to_string()))?;
    if caller.role == Role::Robot {
        if filter.robot.is_some() && filter.robot != caller.robot {
            return Err(ApiError::Forbidden("a robot lists only its own trials".into()));
        }
        filter.robot = caller.robot.clone();
    }
    let forces = match params.include.as_deref() {
        None => false,
        Some("forces") => true,
        Some(other) => {
            return Err(ApiError::BadRequest(format!(
                "include takes only \"forces\" (each trial with its force samples), not {other:?}"
            )));
        }
    };
    // Pages with force samples run to megabytes: their query and text wait for the client
    // address's turn, so a few hosts asking for many cannot take every core.
    let _turn =
        if forces { Some(state.heavy_answers.turn(client_address(client)).await) } else { None };
    let window = trials::Window { after, limit: limit + 1, max_bytes: MAX_PAGE_BYTES, forces };
    let (rows, cut_short) = trials::list(state.db.reader(), &filter, window).await?;
    let mut page = page::page(rows, limit, |row| row.seq.to_string());
    if cut_short {
        page.next_cursor = page.items.last().map(|last| page::encode_cursor(&last.seq.to_string()));
    }
    page_response(&page)
}

/// The client's address; requests handed to the router in-process share one.
fn client_address(client: Option<Extension<ConnectInfo<SocketAddr>>>) -> IpAddr {
    client.map_or(IpAddr::from([127, 0, 0, 1]), |Extension(ConnectInfo(address))| address.ip())
}

/// The page's JSON written item by item, so the answer is never held twice over as values.
fn page_response(page: &Page<TrialRow>) -> Result<Response, ApiError> {
    let mut body = b"{\"items\":[".to_vec();
    for (n, row) in page.items.iter().enumerate() {
        if n > 0 {
            body.push(b',');
        }
        serde_json::to_writer(&mut body, &StoredTrialAnswer::from(row))
            .map_err(anyhow::Error::from)?;
    }
    body.extend_from_slice(b"],\"next_cursor\":");
    serde_json::to_writer(&mut body, &page.next_cursor).map_err(anyhow::Error::from)?;
    body.push(b'}');
    Ok(([(axum::http::header::CONTENT_TYPE, "application/json")], body).into_response())
}
