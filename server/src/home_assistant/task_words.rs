//! A tag's newest task in the words a caretaker reads on a Home Assistant dashboard.

use pps_schema::TaskState;
use serde_json::{Value, json};

use crate::store::tasks::TaskRow;

/// Home Assistant keeps at most this many characters of a sensor's state.
const MAX_STATE_CHARS: usize = 255;

/// "queued", "being done by el-e-1", "done by el-e-1", "failed: …", with who declined and why.
pub fn words(task: &TaskRow) -> String {
    let robot = task.claimed_by.as_ref().map(ToString::to_string);
    let reason = task.reason.as_deref().filter(|reason| !reason.is_empty());
    let mut said = match task.state {
        TaskState::Queued => "queued".to_owned(),
        TaskState::Claimed => format!("being done by {}", robot.as_deref().unwrap_or("a robot")),
        TaskState::Done => {
            robot.map_or_else(|| "done".to_owned(), |robot| format!("done by {robot}"))
        }
        TaskState::Failed => {
            format!("failed: {}", reason.unwrap_or("the robot's detector saw no change"))
        }
        TaskState::Cancelled => format!("cancelled: {}", reason.unwrap_or("no reason given")),
    };
    if task.is_open() {
        for decline in task.declined() {
            said.push_str(&format!("; {} declined: {}", decline.robot, decline.reason));
        }
    }
    if said.chars().count() > MAX_STATE_CHARS {
        said = said.chars().take(MAX_STATE_CHARS - 1).chain(['…']).collect();
    }
    said
}

/// The task's fields shown as the sensor's attributes.
pub fn attributes(task: &TaskRow) -> Value {
    json!({
        "task": task.id, "action": task.action, "state": task.state,
        "robot": task.claimed_by, "trial": task.trial, "asked_by": task.created_by,
        "asked_at": task.created_at, "updated_at": task.updated_at,
    })
}

#[cfg(test)]
mod tests {
    use pps_schema::{Epc, RobotId};

    use super::*;

    fn task(state: &str) -> TaskRow {
        TaskRow {
            seq: 1,
            id: uuid::Uuid::nil(),
            epc: Epc::parse("1001").unwrap(),
            action: "off".into(),
            robot: None,
            class: None,
            note: None,
            state: state.parse().unwrap(),
            created_by: "Home Assistant bridge".into(),
            created_at: time::macros::datetime!(2026-12-05 10:00 UTC),
            claimed_by: None,
            lease_until: None,
            attempts: 0,
            holders: "[]".into(),
            trial: None,
            reason: None,
            updated_at: time::macros::datetime!(2026-12-05 10:00 UTC),
            declines: "[]".into(),
            expires_at: None,
        }
    }

    #[test]
    fn each_state_reads_in_words() {
        assert_eq!(words(&task("queued")), "queued");
        let mut claimed = task("claimed");
        claimed.claimed_by = Some(RobotId::parse("el-e-1").unwrap());
        assert_eq!(words(&claimed), "being done by el-e-1");
        claimed.state = TaskState::Done;
        assert_eq!(words(&claimed), "done by el-e-1");
        let mut failed = task("failed");
        failed.reason = Some("the lease ran out 3 times".into());
        assert_eq!(words(&failed), "failed: the lease ran out 3 times");
    }

    #[test]
    fn a_queued_task_says_who_declined_and_why() {
        let mut queued = task("queued");
        queued.declines =
            r#"[{"robot": "el-e-1", "reason": "not in its room", "at": "2026-12-05T10:00:01.000Z"}]"#
                .into();
        assert_eq!(words(&queued), "queued; el-e-1 declined: not in its room");
        queued.declines = format!(
            r#"[{{"robot": "el-e-1", "reason": "{}", "at": "2026-12-05T10:00:01.000Z"}}]"#,
            "x".repeat(400)
        );
        assert_eq!(words(&queued).chars().count(), MAX_STATE_CHARS);
    }
}
