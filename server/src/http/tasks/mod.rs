//! `/api/v1/tasks`: a caretaker asks for an action on a tag; robots that can run it claim it
//! under a lease ([`lease`]) and finish it with the trial it ended in (DESIGN §8).

pub mod decline;
pub mod lease;
mod offer;
mod outlook;

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use axum::http::header::LOCATION;
use axum::response::{IntoResponse, Response};
use pps_schema::{Epc, RobotId, TaskState};
use serde::Deserialize;
use uuid::Uuid;

use crate::answers::tasks::TaskAnswer;
use crate::auth::Principal;
use crate::error::ApiError;
use crate::http::extract::{ApiQuery, Caller, JsonBody};
use crate::http::ids::{InPath, Segment, TaskId};
use crate::http::openapi::doc::{Body, Doc, Header, Param, ParamType, Reply};
use crate::http::page;
use crate::identity::Role;
use crate::state::AppState;
use crate::store::robots;
use crate::store::tasks::{self, TaskFilter, TaskRow};
use crate::tasks::ask::ask;
use crate::tasks::availability;
use crate::tasks::request::TaskRequest;

pub const TASK_ID: Param = Param::path("id", ParamType::Uuid, "The task's id")
    .example("3f0c5a8e-9b1d-4e2f-8a7c-6d5e4f3a2b10");

pub const CREATE: Doc =
    Doc::new("createTask", "Ask a robot to do an action on a tag")
        .describe(
            "Optionally only one robot (`robot`) or robots of one class (`class`) may do it. The \
         task waits in the queue until a robot that can run the action claims it.",
        )
        .body(Body::json("new_task", "The tag, its action and optional targets").example(
            r#"{ "epc": "355AB1C60000001000000001", "action": "off", "note": "hallway" }"#,
        ))
        .replies(&[
            Reply::json(201, "Queued", "task").headers(&[Header::Location]),
            Reply::problem(
                422,
                "The tag is unknown, archived or retired, lacks the action, or the targeted robot \
             or class cannot run it; `errors` points at each problem",
            ),
        ]);

pub async fn create(
    State(state): State<AppState>,
    Caller(caller): Caller,
    JsonBody(body): JsonBody,
) -> Result<Response, ApiError> {
    let asked = TaskRequest::parse(&body, state.clock.now())?;
    let row = ask(&state, asked, &caller.name, None).await?;
    let location = format!("/api/v1/tasks/{}", row.id);
    let shown = outlook::shown(&state, &row).await?;
    Ok((StatusCode::CREATED, [(LOCATION, location)], Json(shown)).into_response())
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ListParams {
    state: Option<String>,
    epc: Option<String>,
    robot: Option<String>,
    limit: Option<u32>,
    cursor: Option<String>,
}

const STATES: &[&str] = &TaskState::NAMES;

pub const LIST: Doc = Doc::new("listTasks", "Tasks, newest first")
    .describe(
        "A robot lists only the tasks it holds or held and the queued ones it may claim \
         (its effective entry makes the action available, and the task targets it, its class \
         or anyone); a page may then hold fewer than `limit` items although more follow.",
    )
    .params(&[
        Param::query("state", ParamType::OneOf(STATES), "Only tasks in this state"),
        Param::query("epc", ParamType::Schema("tag/$defs/epc"), "Only tasks on this tag"),
        Param::query(
            "robot",
            ParamType::Schema("robot/$defs/robot_id"),
            "Only tasks this robot holds, did or is named in",
        ),
        Param::LIMIT,
        Param::CURSOR,
    ])
    .replies(&[Reply::page("A page of tasks", "task")]);

pub async fn list(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiQuery(params): ApiQuery<ListParams>,
) -> Result<Json<page::Page<TaskAnswer>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let before = page::decode_position(params.cursor.as_deref())?;
    let asked_state = params
        .state
        .as_deref()
        .map(|asked| {
            asked.parse::<TaskState>().map_err(|_| {
                ApiError::BadRequest(format!(
                    "state is one of {}, not {asked:?}",
                    STATES.join(", ")
                ))
            })
        })
        .transpose()?;
    let epc = params.epc.as_deref().map(Epc::parse_segment).transpose()?;
    let robot = params.robot.as_deref().map(RobotId::parse_segment).transpose()?;
    let visible_to = match (caller.role, &robot) {
        (Role::Robot, Some(asked)) if Some(asked) != caller.robot.as_ref() => {
            return Err(ApiError::Forbidden(
                "a robot lists only tasks it holds or may claim; leave robot out or name yourself"
                    .into(),
            ));
        }
        (Role::Robot, _) => Some(robot_and_class(&state, &caller).await?),
        _ => None,
    };
    let filter = TaskFilter { state: asked_state, epc, robot, visible_to };
    let rows = tasks::list(state.db.reader(), &filter, before, limit + 1).await?;
    let mut page = page::page(rows, limit, |row| row.seq.to_string());
    if let Some((robot, _)) = &filter.visible_to {
        let mut offered = Vec::with_capacity(page.items.len());
        for row in page.items {
            if may_see(&state, robot, &row).await? {
                offered.push(row);
            }
        }
        page.items = offered;
    }
    Ok(Json(page::Page {
        items: outlook::shown_all(&state, &page.items).await?,
        next_cursor: page.next_cursor,
    }))
}

pub const GET: Doc = Doc::new("getTask", "One task")
    .params(&[TASK_ID])
    .replies(&[Reply::json(200, "The task", "task"), Reply::problem(404, "No task has this id")]);

pub async fn get(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TaskId(id)): InPath<TaskId>,
) -> Result<Json<TaskAnswer>, ApiError> {
    let row = find(&state, &id).await?;
    if let Some(robot) = caller.robot.as_ref().filter(|_| caller.role == Role::Robot)
        && !may_see(&state, robot, &row).await?
    {
        return Err(ApiError::Forbidden(format!(
            "robot {robot} neither holds task {} nor may claim it",
            row.id
        )));
    }
    Ok(Json(outlook::shown(&state, &row).await?))
}

pub const CANCEL: Doc = Doc::new("cancelTask", "Cancel a queued or claimed task")
    .describe("Its holder, if any, learns it at its next heartbeat (409) and stops.")
    .params(&[TASK_ID])
    .replies(&[
        Reply::json(200, "Cancelled (or cancelled already)", "task"),
        Reply::problem(404, "No task has this id"),
        Reply::problem(409, "The task is done or failed already"),
    ]);

pub async fn cancel(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TaskId(id)): InPath<TaskId>,
) -> Result<Json<TaskAnswer>, ApiError> {
    let mut tx = state.db.begin_write().await?;
    let reason = format!("cancelled by {}", caller.name);
    let cancelled = tasks::cancel(&mut tx, &id, &reason, state.clock.now()).await?;
    tx.commit().await?;
    if let Some(row) = cancelled {
        state.feed.committed();
        return Ok(Json(TaskAnswer::from(&row)));
    }
    let row = find(&state, &id).await?;
    match row.state {
        TaskState::Cancelled => Ok(Json(TaskAnswer::from(&row))),
        ended => Err(ApiError::Conflict(format!(
            "task {id} is {ended} already (trial {}); only queued or claimed tasks can be \
             cancelled — ask for a new task to undo it",
            row.trial.map_or("none".to_owned(), |trial| trial.to_string())
        ))),
    }
}

/// The task with this id, or 404.
async fn find(state: &AppState, id: &Uuid) -> Result<TaskRow, ApiError> {
    tasks::get(state.db.reader(), id)
        .await?
        .ok_or_else(|| ApiError::NotFound(format!("no task has the id {id}")))
}

/// The caller's robot id and its class (a robot token is always bound to a robot).
async fn robot_and_class(
    state: &AppState,
    caller: &Principal,
) -> Result<(RobotId, Option<String>), ApiError> {
    let robot = caller.own_robot()?.clone();
    let class = robots::get(state.db.reader(), &robot).await?.and_then(|r| r.class);
    Ok((robot, class))
}

/// Whether the task is meant for this robot at all (its targets; not yet its abilities).
fn targets(task: &TaskRow, robot: &RobotId, class: Option<&str>) -> bool {
    task.robot.as_ref().is_none_or(|r| r == robot)
        && task.class.as_deref().is_none_or(|c| Some(c) == class)
}

/// A robot sees the tasks it holds or held, and the queued ones it could claim.
async fn may_see(state: &AppState, robot: &RobotId, row: &TaskRow) -> Result<bool, ApiError> {
    if row.claimed_by.as_ref() == Some(robot) || row.holders().iter().any(|h| h == robot) {
        return Ok(true);
    }
    if row.state != TaskState::Queued || row.robot.as_ref().is_some_and(|r| r != robot) {
        return Ok(false);
    }
    let class = robots::get(state.db.reader(), robot).await?.and_then(|r| r.class);
    if row.class.is_some() && row.class != class {
        return Ok(false);
    }
    Ok(availability::why_not(state, &row.epc, &row.action, robot).await?.is_none())
}
