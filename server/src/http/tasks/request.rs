//! A caretaker's task request, checked: the tag and its action, the robot or class asked for,
//! the note; every problem found is reported at once.

use pps_schema::{Epc, FieldError, RobotId};
use serde_json::Value;

use super::availability;
use crate::error::ApiError;
use crate::state::AppState;
use crate::store::{retired, robots, tags};

/// A note longer than this is not a note.
const MAX_NOTE_CHARS: usize = 500;

/// A create request, parsed; every problem found is reported at once.
pub(crate) struct TaskRequest {
    pub(super) epc: Epc,
    pub(super) action: String,
    pub(super) robot: Option<RobotId>,
    pub(super) class: Option<String>,
    pub(super) note: Option<String>,
}

impl TaskRequest {
    /// A request for `action` on `epc` by any robot that can, with a note.
    pub(crate) fn action_on(epc: Epc, action: String, note: Option<String>) -> Self {
        Self { epc, action, robot: None, class: None, note }
    }

    pub(super) fn parse(body: &Value) -> Result<Self, ApiError> {
        let Some(object) = body.as_object() else {
            return Err(ApiError::invalid_at(
                "",
                "a task is a JSON object, e.g. {\"epc\": \"…\", \"action\": \"off\"}",
            ));
        };
        let mut errors = Vec::new();
        for key in object.keys() {
            if !["epc", "action", "robot", "class", "note"].contains(&key.as_str()) {
                errors.push(FieldError::new(
                    pps_schema::pointer::join("", key),
                    format!("a task has no field {key}; it takes epc, action, robot, class, note"),
                ));
            }
        }
        let mut text = |key: &str, required: bool| match object.get(key) {
            None | Some(Value::Null) if !required => None,
            Some(Value::String(text)) => Some(text.clone()),
            _ => {
                let what = if required { "a string, and required" } else { "a string or null" };
                errors.push(FieldError::new(format!("/{key}"), format!("{key} is {what}")));
                None
            }
        };
        let (epc, action, robot, class, note) = (
            text("epc", true),
            text("action", true),
            text("robot", false),
            text("class", false),
            text("note", false),
        );
        let epc = epc.and_then(|raw| {
            Epc::parse(&raw)
                .map_err(|error| {
                    errors.push(FieldError::new("/epc", format!("{raw:?} is not an EPC: {error}")))
                })
                .ok()
        });
        if action.as_deref() == Some("") {
            errors.push(FieldError::new("/action", "action names one of the tag's actions"));
        }
        let robot = robot.and_then(|raw| {
            RobotId::parse(&raw)
                .map_err(|error| {
                    errors.push(FieldError::new(
                        "/robot",
                        format!("{raw:?} is not a robot id: {error}"),
                    ))
                })
                .ok()
        });
        if let Some(raw) = &class
            && let Err(error) = RobotId::parse(raw)
        {
            errors
                .push(FieldError::new("/class", format!("{raw:?} is not a robot class: {error}")));
        }
        if note.as_ref().is_some_and(|n| n.chars().count() > MAX_NOTE_CHARS) {
            errors.push(FieldError::new(
                "/note",
                format!("a note holds at most {MAX_NOTE_CHARS} characters"),
            ));
        }
        match (epc, action) {
            (Some(epc), Some(action)) if errors.is_empty() => {
                Ok(Self { epc, action, robot, class, note })
            }
            _ => Err(ApiError::Invalid(errors)),
        }
    }

    /// The tag must be active and have the action, and the targets must be able to run it.
    pub(crate) async fn check(&self, state: &AppState) -> Result<(), ApiError> {
        let epc = self.epc.as_hex();
        let tag = match tags::get(state.db.reader(), &self.epc).await? {
            Some(tag) if tag.archived => {
                return Err(ApiError::invalid_at(
                    "/epc",
                    format!("the tag {epc} is archived; a caretaker restores it before asking"),
                ));
            }
            Some(tag) => tag,
            None => {
                let mut conn = state.db.reader().acquire().await?;
                let message = match retired::successor(&mut conn, &self.epc).await? {
                    Some(successor) => format!(
                        "the EPC {epc} was retired when its tag was replaced; ask for the task \
                         on {successor}"
                    ),
                    None => format!("no tag has the EPC {epc}; register the tag first"),
                };
                return Err(ApiError::invalid_at("/epc", message));
            }
        };
        let actions = tag.entry.get("actions").and_then(Value::as_object);
        if !actions.is_some_and(|actions| actions.contains_key(&self.action)) {
            let offered: Vec<&str> =
                actions.map(|a| a.keys().map(String::as_str).collect()).unwrap_or_default();
            return Err(ApiError::invalid_at(
                "/action",
                format!(
                    "the tag {epc} has no action {:?}; it offers {}",
                    self.action,
                    if offered.is_empty() { "none".to_owned() } else { offered.join(", ") }
                ),
            ));
        }
        let mut errors = Vec::new();
        if let Some(robot) = &self.robot {
            let stored = robots::get(state.db.reader(), robot).await?;
            match (&stored, &self.class) {
                (None, _) => errors.push(FieldError::new(
                    "/robot",
                    format!("no robot {robot} is registered; name a registered robot"),
                )),
                (Some(stored), Some(class)) if stored.class.as_deref() != Some(class) => errors
                    .push(FieldError::new(
                        "/class",
                        format!(
                            "robot {robot} is of class {}, not {class}; name one of the two",
                            stored.class.as_deref().unwrap_or("none")
                        ),
                    )),
                _ => {}
            }
            if stored.is_some()
                && let Some(reason) =
                    availability::why_not(state, &self.epc, &self.action, robot).await?
            {
                errors.push(FieldError::new("/robot", reason));
            }
        } else if let Some(class) = &self.class
            && let Some(reason) =
                availability::why_no_robot_of_class(state, &self.epc, &self.action, class).await?
        {
            errors.push(FieldError::new("/class", reason));
        }
        if errors.is_empty() { Ok(()) } else { Err(ApiError::Invalid(errors)) }
    }
}
