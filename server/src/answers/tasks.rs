//! Answers about tasks: a task as people and robots read it.

use schemars::JsonSchema;
use serde::Serialize;
use time::OffsetDateTime;
use uuid::Uuid;

use pps_schema::{RobotId, TaskState};

use super::{contract, stamp};
use crate::store::tasks::{Decline, TaskRow};

/// A task: what a caretaker asked for, who holds it, how it ended.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "task")]
pub struct TaskAnswer {
    pub id: Uuid,
    #[schemars(with = "contract::Epc")]
    pub epc: pps_schema::Epc,
    pub action: String,
    /// The one robot it is meant for; `null` for any.
    #[schemars(with = "Option<contract::RobotId>")]
    pub robot: Option<RobotId>,
    /// The robot class it is meant for; `null` for any.
    #[schemars(with = "Option<contract::RobotId>")]
    pub class: Option<String>,
    pub note: Option<String>,
    #[schemars(with = "contract::TaskState")]
    pub state: TaskState,
    pub created_by: String,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub created_at: OffsetDateTime,
    /// The holder; once ended, the robot that ended it.
    #[schemars(with = "Option<contract::RobotId>")]
    pub claimed_by: Option<RobotId>,
    #[serde(with = "stamp::option")]
    #[schemars(with = "Option<stamp::DateTime>")]
    pub lease_until: Option<OffsetDateTime>,
    /// How many times a robot claimed it.
    #[schemars(range(min = 0))]
    pub attempts: i64,
    /// Every robot that held it, in order.
    #[schemars(with = "Vec<contract::RobotId>")]
    pub holders: Vec<RobotId>,
    /// The trial that finished it.
    pub trial: Option<Uuid>,
    pub reason: Option<String>,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub updated_at: OffsetDateTime,
    /// Every robot that declined it and why, in order; it is never offered to them again.
    pub declined: Vec<Declined>,
    /// When it expires unless a robot took it (or, holding it, finished it); null for never
    /// (tasks asked for before tasks could expire).
    #[serde(with = "stamp::option")]
    #[schemars(with = "Option<stamp::DateTime>")]
    pub expires_at: Option<OffsetDateTime>,
    /// Whether it ended because it expired: it is then `cancelled`, and `reason` says so in
    /// words.
    pub expired: bool,
    /// While queued: the robots online (seen in the last minute) that may take it now.
    #[schemars(with = "Vec<contract::RobotId>")]
    pub waiting_for: Vec<RobotId>,
    /// While queued and no robot online may take it: why, in words (who declined and why, who
    /// could but is offline, or that no robot can). It stays queued until a robot can take it.
    pub stuck: Option<String>,
}

/// A robot's word that it cannot do a task, and why.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "task_decline_record")]
pub struct Declined {
    #[schemars(with = "contract::RobotId")]
    pub robot: RobotId,
    /// Why, in a caretaker's words, and what they can do about it when the robot knows.
    pub reason: String,
    /// What the robot itself said when it stopped, for whoever looks further; null when it
    /// said nothing more.
    pub detail: Option<String>,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub at: OffsetDateTime,
}

impl From<Decline> for Declined {
    fn from(decline: Decline) -> Self {
        Self {
            at: decline.at,
            robot: decline.robot,
            reason: decline.reason,
            detail: decline.detail,
        }
    }
}

impl From<&TaskRow> for TaskAnswer {
    /// The task as stored; `waiting_for` and `stuck` are worked out when people read a queued
    /// task (the HTTP layer's outlook).
    fn from(task: &TaskRow) -> Self {
        Self {
            id: task.id,
            epc: task.epc.clone(),
            action: task.action.clone(),
            robot: task.robot.clone(),
            class: task.class.clone(),
            note: task.note.clone(),
            state: task.state,
            created_by: task.created_by.clone(),
            created_at: task.created_at,
            claimed_by: task.claimed_by.clone(),
            lease_until: task.lease_until,
            attempts: task.attempts,
            holders: task.holders(),
            trial: task.trial,
            reason: task.reason.clone(),
            updated_at: task.updated_at,
            declined: task.declined().into_iter().map(Declined::from).collect(),
            expires_at: task.expires_at,
            expired: task.expired(),
            waiting_for: Vec::new(),
            stuck: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use serde_json::{Value, json};

    use super::*;

    #[test]
    fn a_task_answers_with_every_field_of_the_contract_and_stored_times_unchanged() {
        let task = TaskRow {
            seq: 7,
            id: Uuid::nil(),
            epc: pps_schema::Epc::parse("E20034120000000000001001").unwrap(),
            action: "off".into(),
            robot: None,
            class: Some("el-e".into()),
            note: None,
            state: TaskState::Claimed,
            created_by: "nurse".into(),
            created_at: time::macros::datetime!(2026-03-04 05:06:07.089 UTC),
            claimed_by: Some(RobotId::parse("el-e-1").unwrap()),
            lease_until: Some(time::macros::datetime!(2026-03-04 05:07:07.089 UTC)),
            attempts: 1,
            holders: r#"["el-e-1"]"#.into(),
            trial: None,
            reason: None,
            updated_at: time::macros::datetime!(2026-03-04 05:06:08.000 UTC),
            declines:
                r#"[{"robot": "pr2-1", "reason": "no arm", "at": "2026-03-04T05:06:07.500Z"}]"#
                    .into(),
            expires_at: None,
        };
        let answer = serde_json::to_value(TaskAnswer::from(&task)).unwrap();
        assert_eq!(
            answer,
            json!({
                "id": "00000000-0000-0000-0000-000000000000",
                "epc": "E20034120000000000001001",
                "action": "off",
                "robot": null,
                "class": "el-e",
                "note": null,
                "state": "claimed",
                "created_by": "nurse",
                "created_at": "2026-03-04T05:06:07.089Z",
                "claimed_by": "el-e-1",
                "lease_until": "2026-03-04T05:07:07.089Z",
                "attempts": 1,
                "holders": ["el-e-1"],
                "trial": null,
                "reason": null,
                "updated_at": "2026-03-04T05:06:08.000Z",
                "declined": [
                    {
                        "robot": "pr2-1",
                        "reason": "no arm",
                        "detail": null,
                        "at": "2026-03-04T05:06:07.500Z"
                    }
                ],
                "expires_at": null,
                "expired": false,
                "waiting_for": [],
                "stuck": Value::Null
            })
        );
    }
}
