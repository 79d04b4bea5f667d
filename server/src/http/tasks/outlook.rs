//! What a queued task waits for, in words: the robots that could take it now, or why none will
//! (who declined and why, who could but is offline, that no robot can), so a caretaker learns
//! it within seconds instead of after three leases run out.
//!
//! Worked out when a task is read, from the robots, their effective entries and when each was
//! last seen, so it is never stale and nothing is stored. A task that nobody can take stays
//! queued: a robot that comes online or is given the ability later may still take it, and the
//! caretaker, told why it waits, may cancel it.

use std::collections::HashMap;
use std::time::Duration;

use pps_schema::{Epc, RobotId, TaskState};

use super::targets;
use crate::answers::tasks::TaskAnswer;
use crate::error::ApiError;
use crate::robots::presence::ONLINE_WITHIN;
use crate::state::AppState;
use crate::store::robots::{self, StoredRobot};
use crate::store::tasks::TaskRow;
use crate::tasks::availability::why_not;

/// More robots than any home has: the outlook looks at every one.
const MAX_ROBOTS: u32 = 10_000;

/// The task as the API shows it to people: its row with `waiting_for` and `stuck`.
pub async fn shown(state: &AppState, task: &TaskRow) -> Result<TaskAnswer, ApiError> {
    Look::new(state, std::slice::from_ref(task)).await?.show(task).await
}

/// [`shown`] for many tasks, looking at the robots once.
pub async fn shown_all(state: &AppState, tasks: &[TaskRow]) -> Result<Vec<TaskAnswer>, ApiError> {
    let mut look = Look::new(state, tasks).await?;
    let mut shown = Vec::with_capacity(tasks.len());
    for task in tasks {
        shown.push(look.show(task).await?);
    }
    Ok(shown)
}

/// The robots, looked up once for a page of tasks, and which of them can run what.
struct Look<'a> {
    state: &'a AppState,
    robots: Vec<StoredRobot>,
    can: HashMap<(Epc, String, RobotId), Option<String>>,
}

impl<'a> Look<'a> {
    async fn new(state: &'a AppState, tasks: &[TaskRow]) -> Result<Self, ApiError> {
        let robots = if tasks.iter().any(|task| task.state == TaskState::Queued) {
            robots::list(state.db.reader(), None, MAX_ROBOTS).await?
        } else {
            Vec::new()
        };
        Ok(Self { state, robots, can: HashMap::new() })
    }

    /// The task with, while it is queued, what it waits for.
    async fn show(&mut self, task: &TaskRow) -> Result<TaskAnswer, ApiError> {
        let mut shown = TaskAnswer::from(task);
        if task.state == TaskState::Queued {
            (shown.waiting_for, shown.stuck) = self.at(task).await?;
        }
        Ok(shown)
    }

    /// Why `robot` cannot run the task's action, or `None` when it can.
    async fn why_not(
        &mut self,
        task: &TaskRow,
        robot: &RobotId,
    ) -> Result<Option<String>, ApiError> {
        let key = (task.epc.clone(), task.action.clone(), robot.clone());
        if let Some(known) = self.can.get(&key) {
            return Ok(known.clone());
        }
        let why = why_not(self.state, &task.epc, &task.action, robot).await?;
        self.can.insert(key, why.clone());
        Ok(why)
    }

    /// The robots that could take the queued task now, and, when there are none, why.
    async fn at(&mut self, task: &TaskRow) -> Result<(Vec<RobotId>, Option<String>), ApiError> {
        let mut online = Vec::new();
        let mut offline = Vec::new();
        let mut cannot = Vec::new();
        let now = self.state.clock.now();
        let meant_for: Vec<RobotId> = self
            .robots
            .iter()
            .filter(|robot| targets(task, &robot.id, robot.class.as_deref()))
            .filter(|robot| !task.declined_by(&robot.id))
            .map(|robot| robot.id.clone())
            .collect();
        for robot in meant_for {
            match self.why_not(task, &robot).await? {
                Some(why) => cannot.push(format!("{robot}: {why}")),
                None if self.state.presence.online(robot.as_str(), now) => online.push(robot),
                None => {
                    let seen = self.state.presence.seen_ago(robot.as_str(), now);
                    offline.push(match seen {
                        Some(ago) => format!("{robot} was last seen {}", ago_in_words(ago)),
                        None => format!("{robot} has not been seen yet"),
                    });
                }
            }
        }
        if !online.is_empty() {
            return Ok((online, None));
        }
        let declined = task.declined();
        let mut why: Vec<String> =
            declined.iter().map(|d| format!("{} declined: {}", d.robot, d.reason)).collect();
        why.push(match (offline.is_empty(), declined.is_empty(), cannot.is_empty()) {
            (false, _, _) => format!(
                "no robot that can do it is online (seen in the last {} seconds): {}",
                ONLINE_WITHIN.as_secs(),
                offline.join(", ")
            ),
            (true, false, _) => "no other robot can do it".to_owned(),
            (true, true, false) => format!("no robot can do it ({})", cannot.join("; ")),
            (true, true, true) => "no registered robot is meant for it".to_owned(),
        });
        Ok((online, Some(why.join("; "))))
    }
}

/// "40 seconds ago", "5 minutes ago", "3 hours ago", "2 days ago".
fn ago_in_words(ago: Duration) -> String {
    let seconds = ago.as_secs();
    match seconds {
        0..120 => format!("{seconds} seconds ago"),
        120..7_200 => format!("{} minutes ago", seconds / 60),
        7_200..172_800 => format!("{} hours ago", seconds / 3_600),
        _ => format!("{} days ago", seconds / 86_400),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn how_long_ago_reads_in_the_largest_sensible_unit() {
        assert_eq!(ago_in_words(Duration::from_secs(61)), "61 seconds ago");
        assert_eq!(ago_in_words(Duration::from_secs(300)), "5 minutes ago");
        assert_eq!(ago_in_words(Duration::from_secs(3 * 3_600 + 59)), "3 hours ago");
        assert_eq!(ago_in_words(Duration::from_secs(2 * 86_400)), "2 days ago");
    }
}
