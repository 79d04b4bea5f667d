//! Whether a robot can run a task's action: what its effective entry says (DESIGN §3's
//! `unavailable_actions`), so tasks are offered by the very rule robots read.

use std::collections::BTreeMap;

use pps_schema::{Epc, RobotId};
use serde::Deserialize;
use serde_json::Value;

use crate::effective_entry::entry_for;
use crate::error::ApiError;
use crate::state::AppState;
use crate::store::robots;

/// The parts of an effective entry that decide availability.
#[derive(Deserialize)]
struct Effective {
    entry: Actions,
    unavailable_actions: Vec<Unavailable>,
}

#[derive(Deserialize)]
struct Actions {
    #[serde(default)]
    actions: BTreeMap<String, Value>,
}

#[derive(Deserialize)]
struct Unavailable {
    action: String,
    reason: String,
}

/// Why `robot` cannot run `action` on `epc`, or `None` when it can.
pub async fn why_not(
    state: &AppState,
    epc: &Epc,
    action: &str,
    robot: &RobotId,
) -> Result<Option<String>, ApiError> {
    let cached = match entry_for(state, epc, robot).await {
        Ok(cached) => cached,
        // An archived or retired tag: nothing on it can be done.
        Err(ApiError::NotFound(why)) => return Ok(Some(why)),
        Err(other) => return Err(other),
    };
    let effective: Effective = serde_json::from_slice(&cached.body).map_err(|error| {
        ApiError::Internal(anyhow::anyhow!("an effective entry does not parse: {error}"))
    })?;
    if !effective.entry.actions.contains_key(action) {
        return Ok(Some(format!("the tag {epc} has no action {action}")));
    }
    Ok(effective.unavailable_actions.into_iter().find(|u| u.action == action).map(|u| u.reason))
}

/// Why no registered robot of `class` can run `action` on `epc`, or `None` when one can.
pub async fn why_no_robot_of_class(
    state: &AppState,
    epc: &Epc,
    action: &str,
    class: &str,
) -> Result<Option<String>, ApiError> {
    let members = robots::of_class(state.db.reader(), class).await?;
    if members.is_empty() {
        return Ok(Some(format!(
            "no robot of class {class} is registered; an admin registers one with \
             PUT /api/v1/robots/{{robot}}"
        )));
    }
    let mut reasons = Vec::new();
    for robot in &members {
        match why_not(state, epc, action, &robot.id).await? {
            None => return Ok(None),
            Some(reason) => reasons.push(reason),
        }
    }
    Ok(Some(format!("no robot of class {class} can {action}: {}", reasons.join("; "))))
}
