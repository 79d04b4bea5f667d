//! `/api/v1/robots`: the robot registry.

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use pps_schema::{Robot, RobotId};
use serde_json::Value;

use crate::accept::accept;
use crate::answers::robots::StoredRobotAnswer;
use crate::error::ApiError;
use crate::http::extract::{ApiQuery, Caller, JsonBody};
use crate::http::ids::InPath;
use crate::http::openapi::doc::{Body, Doc, Param, Reply};
use crate::http::page::{self, Page, PageParams};
use crate::state::AppState;
use crate::store::robots::{self, RobotWrite, StoredRobot};

pub const LIST: Doc = Doc::new("listRobots", "List the robots, by id")
    .params(&[Param::LIMIT, Param::CURSOR])
    .replies(&[Reply::page("A page of robots", "stored_robot")]);

pub async fn list(
    State(state): State<AppState>,
    ApiQuery(params): ApiQuery<PageParams>,
) -> Result<Json<Page<StoredRobotAnswer>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = params.cursor.as_deref().map(page::decode_cursor).transpose()?;
    let rows = robots::list(state.db.reader(), after.as_deref(), limit + 1).await?;
    let page = page::page(rows, limit, |robot| robot.id.to_string());
    let items = page.items.iter().map(|robot| with_presence(&state, robot)).collect();
    Ok(Json(Page { items, next_cursor: page.next_cursor }))
}

pub const GET: Doc =
    Doc::new("getRobot", "One robot, with when it last called").params(&[Param::ROBOT]).replies(&[
        Reply::json(200, "The robot", "stored_robot"),
        Reply::problem(404, "No robot has this id"),
    ]);

pub async fn get(
    State(state): State<AppState>,
    InPath(robot): InPath<RobotId>,
) -> Result<Json<StoredRobotAnswer>, ApiError> {
    let stored = robots::get(state.db.reader(), &robot).await?.ok_or_else(|| {
        ApiError::NotFound(format!(
            "no robot has the id {robot}; an admin registers it with PUT /api/v1/robots/{robot}"
        ))
    })?;
    Ok(Json(with_presence(&state, &stored)))
}

pub const PUT: Doc = Doc::new("putRobot", "Register a robot or change it")
    .params(&[Param::ROBOT])
    .body(Body::json("robot", "The robot; its id, when given, must be the one in the path"))
    .replies(&[
        Reply::json(200, "Changed (or unchanged)", "stored_robot"),
        Reply::json(201, "Registered", "stored_robot"),
        Reply::INVALID,
    ]);

pub async fn put(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(robot): InPath<RobotId>,
    JsonBody(body): JsonBody,
) -> Result<Response, ApiError> {
    let (robot, body) = accept::<Robot>(Some(&robot), body)?;
    let written = robots::put(&state.db, &robot, &body, &caller.name).await?;
    if written != RobotWrite::Unchanged {
        // Class, capabilities and limits shape every effective entry this robot reads.
        state.effective.clear();
        state.feed.committed();
    }
    let stored = StoredRobot {
        id: robot,
        class: body.get("class").and_then(Value::as_str).map(str::to_owned),
        document: Some(body),
    };
    let status = if written == RobotWrite::Created { StatusCode::CREATED } else { StatusCode::OK };
    Ok((status, Json(with_presence(&state, &stored))).into_response())
}

fn with_presence(state: &AppState, robot: &StoredRobot) -> StoredRobotAnswer {
    StoredRobotAnswer::new(robot, state.presence.last_seen(robot.id.as_str()))
}
