//! `POST /api/v1/tasks/{id}/decline`: a robot that cannot do a task says so, in words, instead
//! of letting its lease run out.
//!
//! Who may decline: the robot that holds the task, or any robot the queued task is meant for
//! (it targets that robot, its class or anyone), whether or not the task was offered to it yet:
//! a robot that knows it cannot do a task spares the others waiting for it. The task goes back
//! to the queue and is never offered to that robot again. Declining twice is answered with the
//! task as it is; an ended task, or one another robot holds, cannot be declined (409).

use axum::Json;
use axum::extract::State;
use pps_schema::{FieldError, MAX_DECLINE_REASON_CHARS, RobotId, TaskState};
use serde_json::Value;

use super::{TASK_ID, find, outlook, targets};
use crate::answers::tasks::TaskAnswer;
use crate::error::ApiError;
use crate::http::extract::{Caller, JsonBody};
use crate::http::ids::{InPath, TaskId};
use crate::http::openapi::doc::{Body, Doc, Reply};
use crate::state::AppState;
use crate::store::robots;
use crate::store::tasks::{self, TaskRow};

pub const DECLINE: Doc = Doc::new("declineTask", "Say this robot cannot do a task, and why")
    .describe(
        "By the robot that holds the task, or a robot the queued task is meant for. The task \
         goes back to the queue for the other robots and is never offered to this robot \
         again; its `declined` lists who declined and why. Declining again is answered with \
         the task as it is.",
    )
    .params(&[TASK_ID])
    .body(
        Body::json("task_decline", "Why this robot cannot do the task, in plain words")
            .example(r#"{ "reason": "no device in its room has this tag" }"#),
    )
    .replies(&[
        Reply::json(200, "The task, back in the queue, with this decline", "task"),
        Reply::problem(403, "The task is not meant for this robot and it never held it"),
        Reply::problem(404, "No task has this id"),
        Reply::problem(409, "The task has ended, or another robot holds it"),
        Reply::problem(422, "The reason is missing, empty, too long or not plain words"),
    ]);

pub async fn decline(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(TaskId(id)): InPath<TaskId>,
    JsonBody(body): JsonBody,
) -> Result<Json<TaskAnswer>, ApiError> {
    let robot = caller.own_robot()?;
    let DeclineBody { reason, detail } = parse_decline(&body)?;
    let class = robots::get(state.db.reader(), robot).await?.and_then(|r| r.class);
    let task = find(&state, &id).await?;
    if let Some(refused) = refusal(&task, robot, class.as_deref()) {
        return Err(refused);
    }
    let mut tx = state.db.begin_write().await?;
    let declined =
        tasks::decline(&mut tx, &id, robot, &reason, detail.as_deref(), state.clock.now()).await?;
    tx.commit().await?;
    let task = match declined {
        Some(task) => {
            // Back in the queue: the feed's pump wakes the robots waiting in line.
            state.feed.committed();
            task
        }
        // Declined already, or the task changed between the look and the write.
        None => {
            let task = find(&state, &id).await?;
            if let Some(refused) = refusal(&task, robot, class.as_deref()) {
                return Err(refused);
            }
            task
        }
    };
    Ok(Json(outlook::shown(&state, &task).await?))
}

/// Why `robot` may not decline `task` now; `None` when it may, or did already.
fn refusal(task: &TaskRow, robot: &RobotId, class: Option<&str>) -> Option<ApiError> {
    if task.declined_by(robot) {
        return None;
    }
    let held = task.claimed_by.as_ref() == Some(robot) || task.holders().contains(robot);
    if !held && !targets(task, robot, class) {
        return Some(ApiError::Forbidden(format!(
            "task {} is not meant for robot {robot}; a robot declines only tasks it holds or \
             that are meant for it",
            task.id
        )));
    }
    match (task.state, task.claimed_by.as_ref()) {
        (TaskState::Queued, _) => None,
        (TaskState::Claimed, Some(holder)) if holder == robot => None,
        (TaskState::Claimed, Some(holder)) => Some(ApiError::Conflict(format!(
            "robot {holder} holds task {} now; a robot declines a task it holds or one \
             waiting in the queue",
            task.id
        ))),
        (ended, _) => Some(ApiError::Conflict(format!(
            "task {} is {ended} already; there is nothing left to decline",
            task.id
        ))),
    }
}

/// Why a robot declines a task.
// As `parse_decline` returns it.
#[derive(Debug, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "task_decline")]
pub struct DeclineBody {
    /// Why this robot cannot do the task, in words a caretaker knows, and what they can do
    /// about it when the robot knows: one line.
    #[schemars(length(min = 1, max = MAX_DECLINE_REASON_CHARS))]
    #[schemars(regex(pattern = PLAIN_LINE))]
    pub reason: String,
    /// What the robot itself said when it stopped, for whoever looks further: one line. The
    /// web UI shows it on request, under the reason.
    #[schemars(length(min = 1, max = MAX_DECLINE_REASON_CHARS))]
    #[schemars(regex(pattern = PLAIN_LINE))]
    pub detail: Option<String>,
}

/// One line of text with at least one character that is neither a space nor a control one.
const PLAIN_LINE: &str = "^[^\\u0000-\\u001f\\u007f-\\u009f]*[^\\s\\u0000-\\u001f\\u007f-\\u009f][^\\u0000-\\u001f\\u007f-\\u009f]*$";

/// The decline body: `{"reason": "...", "detail": "..."}`, each a line of plain words of 1 to
/// 500 characters; `detail` may be left out.
fn parse_decline(body: &Value) -> Result<DeclineBody, ApiError> {
    let Some(object) = body.as_object() else {
        return Err(ApiError::invalid_at(
            "",
            "a decline is a JSON object: {\"reason\": \"why this robot cannot do it\"}",
        ));
    };
    let mut errors: Vec<FieldError> = object
        .keys()
        .filter(|key| !matches!(key.as_str(), "reason" | "detail"))
        .map(|key| {
            FieldError::new(
                pps_schema::pointer::join("", key),
                format!("a decline has no field {key}; it takes reason and, if you like, detail"),
            )
        })
        .collect();
    let reason = match object.get("reason") {
        None | Some(Value::Null) => {
            errors.push(FieldError::new(
                "/reason",
                "reason says in words why this robot cannot do the task",
            ));
            None
        }
        Some(reason) => one_line("reason", reason, &mut errors),
    };
    let detail = match object.get("detail") {
        None | Some(Value::Null) => None,
        Some(detail) => one_line("detail", detail, &mut errors),
    };
    match reason {
        Some(reason) if errors.is_empty() => Ok(DeclineBody { reason, detail }),
        _ => Err(ApiError::Invalid(errors)),
    }
}

/// `value` trimmed, when it is one line of plain words within bounds; otherwise why not, in
/// `errors`.
fn one_line(field: &str, value: &Value, errors: &mut Vec<FieldError>) -> Option<String> {
    let pointer = format!("/{field}");
    let Some(line) = value.as_str().map(str::trim) else {
        errors.push(FieldError::new(pointer, format!("{field} is a string of plain words")));
        return None;
    };
    let chars = line.chars().count();
    let wrong = if line.is_empty() {
        format!("{field} is empty; say it in words")
    } else if chars > MAX_DECLINE_REASON_CHARS {
        format!("{field} has {chars} characters; say it in at most {MAX_DECLINE_REASON_CHARS}")
    } else if line.chars().any(char::is_control) {
        format!("{field} is one line of plain words, without line breaks or control characters")
    } else {
        return Some(line.to_owned());
    };
    errors.push(FieldError::new(pointer, wrong));
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_reason_is_one_line_of_words_within_bounds() {
        let words = "no device in its room has this tag";
        assert_eq!(
            parse_decline(&json!({ "reason": format!("  {words} ") })).unwrap().reason,
            words
        );
        for bad in [
            json!({}),
            json!({ "reason": "  " }),
            json!({ "reason": 7 }),
            json!({ "reason": "x".repeat(MAX_DECLINE_REASON_CHARS + 1) }),
            json!({ "reason": "two\nlines" }),
            json!({ "reason": "fine", "robot": "el-e-1" }),
            json!("fine"),
            json!({ "reason": "fine", "detail": "" }),
            json!({ "reason": "fine", "detail": ["no"] }),
            json!({ "reason": "fine", "detail": "two\nlines" }),
            json!({ "reason": null, "detail": "fine" }),
        ] {
            assert!(matches!(parse_decline(&bad), Err(ApiError::Invalid(_))), "{bad} is refused");
        }
        let longest = "é".repeat(MAX_DECLINE_REASON_CHARS);
        assert_eq!(parse_decline(&json!({ "reason": longest })).unwrap().reason, longest);
    }

    #[test]
    fn the_robots_own_words_come_apart_from_the_reason_and_may_be_left_out() {
        let with = json!({ "reason": "move the red towel away", "detail": " red region 35 cm " });
        let body = parse_decline(&with).unwrap();
        assert_eq!(body.reason, "move the red towel away");
        assert_eq!(body.detail.as_deref(), Some("red region 35 cm"));
        let without = parse_decline(&json!({ "reason": "not in its room", "detail": null }));
        assert_eq!(without.unwrap().detail, None);
    }
}
