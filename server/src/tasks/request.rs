//! A caretaker's task request, checked: the tag and its action, the robot or class asked for,
//! the note; every problem found is reported at once.

use pps_schema::{Epc, FieldError, RobotId};
use serde_json::Value;

use super::availability;
use crate::answers::{contract, stamp};
use crate::clock;
use crate::error::ApiError;
use crate::state::AppState;
use crate::store::{retired, robots, tags};

/// A note longer than this is not a note.
const MAX_NOTE_CHARS: usize = 500;
/// How long a task waits for a robot unless the caretaker says otherwise: a day.
pub const DEFAULT_EXPIRY: time::Duration = time::Duration::days(1);
/// The latest a task may expire: a wish older than a month is no longer a wish.
pub const MAX_EXPIRY: time::Duration = time::Duration::days(30);

/// A task to ask for: the tag and its action, optionally the robot or class to do it, a note
/// and when it expires.
// As `TaskRequest::parse` reads it before any field is checked (`None`: left out, null, or not
// a string).
#[derive(Debug, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "new_task")]
pub struct NewTask {
    #[schemars(required, with = "contract::Epc")]
    pub epc: Option<String>,
    /// One of the tag's actions.
    #[schemars(required, with = "String", length(min = 1))]
    pub action: Option<String>,
    /// The one robot to do it; any robot that can when left out.
    #[schemars(with = "Option<contract::RobotId>")]
    pub robot: Option<String>,
    /// The robot class to do it; any class when left out.
    #[schemars(with = "Option<contract::RobotId>")]
    pub class: Option<String>,
    #[schemars(length(max = MAX_NOTE_CHARS))]
    pub note: Option<String>,
    /// When the task expires unless a robot took it: later than now and at most 30 days ahead.
    /// Left out or null: a day after it is asked for.
    #[schemars(with = "Option<stamp::DateTime>")]
    pub expires_at: Option<String>,
}

/// A create request, parsed; every problem found is reported at once.
pub(crate) struct TaskRequest {
    pub(super) epc: Epc,
    pub(super) action: String,
    pub(super) robot: Option<RobotId>,
    pub(super) class: Option<String>,
    pub(super) note: Option<String>,
    /// When the task expires unless a robot took it.
    pub(super) expires_at: time::OffsetDateTime,
}

impl TaskRequest {
    /// A request for `action` on `epc` by any robot that can, with a note, expiring after the
    /// default time from `now`.
    pub(crate) fn action_on(
        epc: Epc,
        action: String,
        note: Option<String>,
        now: time::OffsetDateTime,
    ) -> Self {
        let expires_at = now + DEFAULT_EXPIRY;
        Self { epc, action, robot: None, class: None, note, expires_at }
    }

    /// Parses a request made at `now` (its expiry must lie ahead of it).
    pub(crate) fn parse(body: &Value, now: time::OffsetDateTime) -> Result<Self, ApiError> {
        let Some(object) = body.as_object() else {
            return Err(ApiError::invalid_at(
                "",
                "a task is a JSON object, e.g. {\"epc\": \"…\", \"action\": \"off\"}",
            ));
        };
        let mut errors = Vec::new();
        for key in object.keys() {
            if !["epc", "action", "robot", "class", "note", "expires_at"].contains(&key.as_str()) {
                errors.push(FieldError::new(
                    pps_schema::pointer::join("", key),
                    format!(
                        "a task has no field {key}; it takes epc, action, robot, class, note, \
                         expires_at"
                    ),
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
        let NewTask { epc, action, robot, class, note, expires_at } = NewTask {
            epc: text("epc", true),
            action: text("action", true),
            robot: text("robot", false),
            class: text("class", false),
            note: text("note", false),
            expires_at: text("expires_at", false),
        };
        let expires_at = expiry(expires_at.as_deref(), now)
            .map_err(|message| errors.push(FieldError::new("/expires_at", message)))
            .ok();
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
        match (epc, action, expires_at) {
            (Some(epc), Some(action), Some(expires_at)) if errors.is_empty() => {
                Ok(Self { epc, action, robot, class, note, expires_at })
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

/// When a task asked for `now` expires: the time asked for (RFC 3339, later than now and at
/// most [`MAX_EXPIRY`] ahead), or [`DEFAULT_EXPIRY`] from now when none was.
fn expiry(asked: Option<&str>, now: time::OffsetDateTime) -> Result<time::OffsetDateTime, String> {
    let Some(text) = asked else {
        return Ok(now + DEFAULT_EXPIRY);
    };
    let Some(at) = clock::parse(text) else {
        return Err(format!(
            "{text:?} is not a time; expires_at is an RFC 3339 time such as \
             2030-01-01T18:00:00Z"
        ));
    };
    if at <= now {
        return Err(format!("{text} has passed; a task expires later than when it is asked for"));
    }
    if at > now + MAX_EXPIRY {
        return Err(format!(
            "{text} is more than {} days ahead; ask again later if it is still wanted then",
            MAX_EXPIRY.whole_days()
        ));
    }
    Ok(at)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_task_expires_in_a_day_unless_asked_otherwise_within_a_month() {
        let now = clock::parse("2030-01-01T12:00:00Z").unwrap();
        assert_eq!(expiry(None, now).unwrap(), now + time::Duration::days(1));
        let asked = expiry(Some("2030-01-01T13:30:00+01:00"), now).unwrap();
        assert_eq!(asked, now + time::Duration::minutes(30));
        for refused in ["2030-01-01T12:00:00Z", "2030-02-01T12:00:01Z", "tomorrow", ""] {
            assert!(expiry(Some(refused), now).is_err(), "{refused}");
        }
        assert!(expiry(Some("2030-01-31T12:00:00Z"), now).is_ok(), "thirty days is the most");
    }
}
