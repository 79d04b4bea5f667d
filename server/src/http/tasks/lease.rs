//! Claim, heartbeat and finish: a robot holds a task under a lease it keeps alive, and ends
//! it with the trial the task ended in.
//!
//! A claim with `wait` long-polls: the robot waits in line on the [`WaitingLine`] and is answered
//! as soon as a task it should get appears, not at the end of the wait.
//!
//! [`WaitingLine`]: crate::robots::waiting_line::WaitingLine

use std::time::Duration;

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use pps_schema::{FieldError, Outcome, RobotId, TaskState};
use schemars::JsonSchema;
use serde::Deserialize;
use serde_json::Value;
use uuid::Uuid;

use super::{TASK_ID, find, offer};
use crate::answers::contract;
use crate::answers::tasks::TaskAnswer;
use crate::clock;
use crate::error::ApiError;
use crate::http::extract::{ApiQuery, Caller, JsonBody};
use crate::http::ids::{InPath, TaskId};
use crate::http::openapi::doc::{Body, Doc, Param, ParamType, Reply};
use crate::robots::waiting_line::MAX_WAITING_PER_ROBOT;
use crate::state::AppState;
use crate::store::tasks::{self, TaskRow};
use crate::store::{robots, trials};

/// The longest a claim may wait for a task (DESIGN §8).
pub const MAX_WAIT_SECONDS: u64 = 30;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClaimParams {
    wait: Option<f64>,
}

pub const CLAIM: Doc = Doc::new("claimTask", "Take the next task this robot should do")
    .describe(
        "Offers the oldest task the robot may claim (it targets the robot, its class or \
         anyone, and the robot's effective entry makes the action available), unless a robot \
         waiting longer, or one whose class is reliable for the action, should have it. With \
         `wait`, the answer comes as soon as such a task appears. The robot then holds the \
         task until `lease_until`; heartbeats extend it. A robot holds at most a few tasks \
         at once, and has at most a few claims waiting at once.",
    )
    .params(&[
        Param::ROBOT,
        Param::query(
            "wait",
            ParamType::Integer { min: 0, max: MAX_WAIT_SECONDS as i64 },
            "Seconds to wait for a task when none is there now (default 0)",
        ),
    ])
    .replies(&[
        Reply::json(200, "The task, claimed by this robot until lease_until", "task"),
        Reply::empty(204, "No task came within the wait"),
        Reply::problem(
            409,
            "The robot holds as many tasks as one robot may hold at once (`pps-server serve \
             --max-tasks-per-robot`); it finishes or declines one first",
        ),
        Reply::problem(429, "The robot already has as many claims waiting as it may"),
    ]);

pub async fn claim(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(robot): InPath<RobotId>,
    ApiQuery(params): ApiQuery<ClaimParams>,
) -> Result<Response, ApiError> {
    if caller.robot.as_ref() != Some(&robot) {
        return Err(ApiError::Forbidden(format!(
            "a robot claims tasks only for itself: this token is bound to {:?}, not {:?}",
            caller.robot_name(),
            robot.as_str()
        )));
    }
    let wait = match params.wait.unwrap_or(0.0) {
        seconds if (0.0..=MAX_WAIT_SECONDS as f64).contains(&seconds) => {
            Duration::from_secs_f64(seconds)
        }
        seconds => {
            return Err(ApiError::BadRequest(format!(
                "wait is 0 to {MAX_WAIT_SECONDS} seconds, not {seconds}; claim again after an \
                 empty answer"
            )));
        }
    };
    let deadline = tokio::time::Instant::now() + wait;
    let waits = !wait.is_zero();
    // Refused before any read: a robot that claims in a loop costs no database work.
    if waits && state.tasks.waiting_claims(&robot) >= MAX_WAITING_PER_ROBOT {
        return Ok(too_many_waiting(&robot));
    }
    let held = tasks::held_by(state.db.reader(), &robot, state.clock.now()).await?;
    if held.len() >= state.tasks.max_held() {
        return Err(holds_enough(&robot, &held));
    }
    let class = robots::get(state.db.reader(), &robot).await?.and_then(|r| r.class);
    let Ok(place) = state.tasks.join(&robot, class.as_deref(), waits) else {
        return Ok(too_many_waiting(&robot));
    };
    loop {
        let generation = place.begin_look();
        if let Some(task) = offer::claim_next(&state, &place, &robot, class.as_deref()).await? {
            return Ok(Json(TaskAnswer::from(&task)).into_response());
        }
        // Nothing for this robot: it waits, at no cost, until something changes.
        place.looked(generation);
        #[allow(clippy::disallowed_methods, reason = "a long poll ends at its deadline")]
        let timeout = tokio::time::sleep_until(deadline);
        tokio::select! {
            () = place.next_change() => {}
            () = timeout => break,
            // A shutdown does not wait for long polls.
            () = state.feed.closed() => break,
        }
    }
    Ok(StatusCode::NO_CONTENT.into_response())
}

/// The answer to a claim beyond the robot's waiting claims: 429 with `Retry-After`.
fn too_many_waiting(robot: &RobotId) -> Response {
    let mut response = ApiError::TooManyRequests(format!(
        "robot {robot} already has {MAX_WAITING_PER_ROBOT} claims waiting for a task; wait for \
         their answers (each comes by its wait) before claiming again"
    ))
    .into_response();
    let retry = axum::http::HeaderValue::from(crate::error::RETRY_AFTER_SECONDS);
    response.headers_mut().insert(axum::http::header::RETRY_AFTER, retry);
    response
}

/// Why a robot that holds as many tasks as it may gets no other.
fn holds_enough(robot: &RobotId, held: &[Uuid]) -> ApiError {
    let held: Vec<String> = held.iter().map(Uuid::to_string).collect();
    ApiError::Conflict(format!(
        "robot {robot} holds {} task(s) already ({}), as many as one robot may hold at once; \
         finish or decline one before claiming another",
        held.len(),
        held.join(", ")
    ))
}

pub const HEARTBEAT: Doc = Doc::new("heartbeatTask", "Extend the lease on a task this robot holds")
    .params(&[TASK_ID])
    .replies(&[
        Reply::json(200, "The task with its new lease_until", "task"),
        Reply::problem(404, "No task has this id"),
        Reply::problem(
            409,
            "The lease was lost (it ran out, or the task was cancelled or taken over): stop",
        ),
    ]);

pub async fn heartbeat(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TaskId(id)): InPath<TaskId>,
) -> Result<Json<TaskAnswer>, ApiError> {
    let robot = caller.own_robot()?;
    let now = state.clock.now();
    let mut tx = state.db.begin_write().await?;
    let extended = tasks::extend_lease(&mut tx, &id, robot, now, now + state.tasks.lease()).await?;
    tx.commit().await?;
    match extended {
        Some(row) => Ok(Json(TaskAnswer::from(&row))),
        None => Err(not_held(&find(&state, &id).await?, robot)),
    }
}

pub const FINISH: Doc =
    Doc::new("finishTask", "End a task this robot holds with its trial")
        .describe(
            "The trial must be recorded already, by this robot, on the task's tag and action, \
         with this outcome, and it must not have finished another task. A success makes the \
         task `done`, any other outcome `failed`. Repeating the same finish is answered with \
         the ended task; a finish naming another trial or outcome is 409.",
        )
        .params(&[TASK_ID])
        .body(Body::json("task_finish", "The trial the task ended in and its outcome").example(
            r#"{ "trial": "0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10", "outcome": "success" }"#,
        ))
        .replies(&[
            Reply::json(200, "The ended task", "task"),
            Reply::problem(403, "The trial is another robot's, or this robot never held the task"),
            Reply::problem(404, "No task has this id"),
            Reply::problem(
                409,
                "The lease was lost, the trial finished another task, or the task ended with \
                 another trial or outcome",
            ),
            Reply::problem(422, "No such trial, or it is on another tag or action or outcome"),
        ]);

pub async fn finish(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TaskId(id)): InPath<TaskId>,
    JsonBody(body): JsonBody,
) -> Result<Json<TaskAnswer>, ApiError> {
    let robot = caller.own_robot()?;
    let Finish { trial: trial_id, outcome } = parse_finish(&body)?;
    let task = find(&state, &id).await?;
    if let Some(first) = task.trial.filter(|_| task.claimed_by.as_ref() == Some(robot)) {
        // A retry whose first answer was lost: it must say what the first finish said.
        return replayed(&state, task, first, trial_id, outcome).await;
    }
    if task.state != TaskState::Claimed || task.claimed_by.as_ref() != Some(robot) {
        return Err(not_held(&task, robot));
    }
    if let Some(other) = tasks::finished_with(state.db.reader(), &trial_id).await? {
        return Err(trial_used(&trial_id, &other));
    }
    let Some(trial) = trials::get(state.db.reader(), &trial_id).await? else {
        return Err(ApiError::invalid_at(
            "/trial",
            format!(
                "no trial has the id {trial_id}; record it (PUT /api/v1/trials/{trial_id}) \
                 before finishing the task"
            ),
        ));
    };
    if trial.robot != *robot {
        return Err(ApiError::Forbidden(format!(
            "trial {trial_id} was recorded by robot {}; a robot finishes a task with its own trial",
            trial.robot
        )));
    }
    let mut errors = Vec::new();
    if trial.epc != task.epc {
        errors.push(FieldError::new(
            "/trial",
            format!("trial {trial_id} is on the tag {}, the task on {}", trial.epc, task.epc),
        ));
    }
    if trial.action != task.action {
        errors.push(FieldError::new(
            "/trial",
            format!("trial {trial_id} did {}, the task asks for {}", trial.action, task.action),
        ));
    }
    if trial.outcome != outcome.as_str() {
        errors.push(FieldError::new(
            "/outcome",
            format!(
                "trial {trial_id} records the outcome {}, not {}",
                trial.outcome,
                outcome.as_str()
            ),
        ));
    }
    if !errors.is_empty() {
        return Err(ApiError::Invalid(errors));
    }
    let succeeded = outcome == Outcome::Success;
    let reason = (!succeeded).then(|| format!("the robot's trial ended in {}", outcome.as_str()));
    let mut tx = state.db.begin_write().await?;
    let now = state.clock.now();
    let ended =
        tasks::finish(&mut tx, &id, robot, &trial_id, succeeded, reason.as_deref(), now).await?;
    tx.commit().await?;
    match ended {
        Some(row) => {
            state.feed.committed();
            Ok(Json(TaskAnswer::from(&row)))
        }
        // The lease ran out, or the trial finished another task, between the look and the
        // write.
        None => match tasks::finished_with(state.db.reader(), &trial_id).await? {
            Some(other) if other != id => Err(trial_used(&trial_id, &other)),
            _ => Err(not_held(&find(&state, &id).await?, robot)),
        },
    }
}

/// The answer to a finish of a task that already ended with `first`: the ended task when the
/// finish says the same as the one that ended it, 409 when it says something else.
async fn replayed(
    state: &AppState,
    task: TaskRow,
    first: Uuid,
    trial_id: Uuid,
    outcome: Outcome,
) -> Result<Json<TaskAnswer>, ApiError> {
    let recorded = trials::get(state.db.reader(), &first).await?.map(|trial| trial.outcome);
    if trial_id == first && recorded.as_deref() == Some(outcome.as_str()) {
        return Ok(Json(TaskAnswer::from(&task)));
    }
    Err(ApiError::Conflict(format!(
        "task {} is {} already: it was finished with trial {first}{}; a repeated finish must \
         name the same trial and outcome",
        task.id,
        task.state,
        recorded.map(|o| format!(" and the outcome {o}")).unwrap_or_default()
    )))
}

/// Why a trial cannot finish a second task.
fn trial_used(trial: &Uuid, task: &Uuid) -> ApiError {
    ApiError::Conflict(format!(
        "trial {trial} finished task {task} already; a trial finishes one task, so record a new \
         trial for this one"
    ))
}

/// The finish body: the trial that did the task, and how it went.
#[derive(Debug, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "task_finish")]
pub struct Finish {
    /// The recorded trial (its UUID) that did the task.
    pub trial: Uuid,
    #[schemars(with = "contract::Outcome")]
    pub outcome: Outcome,
}

/// The finish body: `{"trial": UUID, "outcome"}`, every problem reported at once.
fn parse_finish(body: &Value) -> Result<Finish, ApiError> {
    let Some(object) = body.as_object() else {
        return Err(ApiError::invalid_at(
            "",
            "a finish is a JSON object: {\"trial\": \"<uuid>\", \"outcome\": \"success\"}",
        ));
    };
    let mut errors = Vec::new();
    for key in object.keys().filter(|k| !["trial", "outcome"].contains(&k.as_str())) {
        errors.push(FieldError::new(
            pps_schema::pointer::join("", key),
            format!("a finish has no field {key}; it takes trial and outcome"),
        ));
    }
    let trial = match object.get("trial").and_then(Value::as_str).map(Uuid::parse_str) {
        Some(Ok(id)) => Some(id),
        _ => {
            errors.push(FieldError::new("/trial", "trial is the id (a UUID) of a recorded trial"));
            None
        }
    };
    let asked = object.get("outcome").and_then(Value::as_str);
    let outcome = match Outcome::ALL.into_iter().find(|o| Some(o.as_str()) == asked) {
        Some(outcome) => Some(outcome),
        None => {
            let names: Vec<&str> = Outcome::ALL.iter().map(|o| o.as_str()).collect();
            errors.push(FieldError::new(
                "/outcome",
                format!("outcome is one of {}", names.join(", ")),
            ));
            None
        }
    };
    match (trial, outcome) {
        (Some(trial), Some(outcome)) if errors.is_empty() => Ok(Finish { trial, outcome }),
        _ => Err(ApiError::Invalid(errors)),
    }
}

/// Why `robot` may not heartbeat or finish `task`: 409 when it held it and lost the lease, 403
/// when it never held it.
fn not_held(task: &TaskRow, robot: &RobotId) -> ApiError {
    let held = task.claimed_by.as_ref() == Some(robot) || task.holders().iter().any(|h| h == robot);
    if !held {
        return ApiError::Forbidden(format!(
            "robot {robot} does not hold task {}; only its holder may heartbeat or finish it",
            task.id
        ));
    }
    let now = match (task.state, task.claimed_by.as_ref()) {
        (TaskState::Claimed, Some(holder)) if holder == robot => format!(
            "its lease ran out at {}; it goes back to the queue",
            task.lease_until.map(clock::format).as_deref().unwrap_or("?")
        ),
        (TaskState::Claimed, Some(other)) => format!("robot {other} holds it now"),
        (TaskState::Queued, _) => "it is back in the queue".to_owned(),
        (ended, _) => format!(
            "it is {ended}{}",
            task.reason.as_deref().map(|r| format!(" ({r})")).unwrap_or_default()
        ),
    };
    ApiError::Conflict(format!(
        "robot {robot} lost its lease on task {}: {now}. Stop working on it and claim the next",
        task.id
    ))
}
