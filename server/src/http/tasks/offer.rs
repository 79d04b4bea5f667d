//! Which task a claiming robot gets: the fairness rule.
//!
//! A robot is offered the oldest task it may claim (the task targets it, its class or anyone,
//! it has not expired, and the robot's effective entry makes the action available) unless
//! another robot waiting in line ranks before it for that task. Robots rank first by whether
//! their class is reliable for the task's action on that tag (the stats' reliable flag), then
//! by when they asked. A robot that steps aside leaves that task to the best-ranked such robot
//! and looks at the next task, for which that robot no longer counts (it takes one task at a
//! time). When a robot that was stepped aside for leaves the line, everyone waiting looks
//! again, so a task passed over is never stranded.

use std::collections::HashMap;

use pps_schema::{Epc, RobotId};

use super::targets;
use crate::error::ApiError;
use crate::robots::waiting_line::{Place, Waiter};
use crate::state::AppState;
use crate::store::learning;
use crate::store::tasks::{self, TaskRow};
use crate::tasks::availability::why_not;

/// Tasks looked at per attempt: the oldest ones this robot can do. It passes over one only
/// for a robot waiting in line, so more than there are robots waiting is never needed.
const CANDIDATES: u32 = 200;

/// A robot's standing for one task: lower is preferred.
fn rank(reliable_classes: &[String], class: Option<&str>, arrival: u64) -> (bool, u64) {
    let reliable = class.is_some_and(|c| reliable_classes.iter().any(|r| r == c));
    (!reliable, arrival)
}

/// What one look found out, so many tasks on the same tag and action cost one check each.
#[derive(Default)]
struct Memo {
    can: HashMap<(Epc, String, RobotId), bool>,
    reliable: HashMap<(Epc, String), Vec<String>>,
}

impl Memo {
    /// Whether `robot` can run the task's action (its effective entry says so) and did not
    /// decline the task.
    async fn can(
        &mut self,
        state: &AppState,
        task: &TaskRow,
        robot: &RobotId,
    ) -> Result<bool, ApiError> {
        if task.declined_by(robot) {
            return Ok(false);
        }
        self.can_run(state, &task.epc, &task.action, robot).await
    }

    /// Whether `robot` can run `action` on `epc`: its effective entry says so.
    async fn can_run(
        &mut self,
        state: &AppState,
        epc: &Epc,
        action: &str,
        robot: &RobotId,
    ) -> Result<bool, ApiError> {
        let key = (epc.clone(), action.to_owned(), robot.clone());
        if let Some(&can) = self.can.get(&key) {
            return Ok(can);
        }
        let can = why_not(state, epc, action, robot).await?.is_none();
        self.can.insert(key, can);
        Ok(can)
    }

    /// The classes reliable for the task's action on its tag.
    async fn reliable(
        &mut self,
        state: &AppState,
        task: &TaskRow,
    ) -> Result<Vec<String>, ApiError> {
        let key = (task.epc.clone(), task.action.clone());
        if let Some(classes) = self.reliable.get(&key) {
            return Ok(classes.clone());
        }
        let classes =
            learning::reliable_classes(state.db.reader(), &task.epc, &task.action).await?;
        self.reliable.insert(key, classes.clone());
        Ok(classes)
    }
}

/// Claims the task this robot should get now, if any.
///
/// What it cannot do is left out in the database, not after reading: the kinds of task (tag
/// and action) open to it are read first and checked against its effective entry, then the
/// oldest tasks of the kinds it can do. However many tasks it cannot do lie ahead, they cost
/// one check per kind, and the task meant for it is found.
pub async fn claim_next(
    state: &AppState,
    place: &Place,
    robot: &RobotId,
    class: Option<&str>,
) -> Result<Option<TaskRow>, ApiError> {
    let reader = state.db.reader();
    let now = state.clock.now();
    let mut memo = Memo::default();
    let mut doable = Vec::new();
    for (epc, action) in tasks::claimable_kinds(reader, robot, class, now).await? {
        if memo.can_run(state, &epc, &action, robot).await? {
            doable.push((epc, action));
        }
    }
    let candidates = tasks::claimable(reader, robot, class, now, &doable, CANDIDATES).await?;
    if candidates.is_empty() {
        return Ok(None);
    }
    let mut others = state.tasks.others(place);
    for task in candidates {
        if !memo.can(state, &task, robot).await? {
            continue;
        }
        if let Some(first) =
            someone_else_first(state, &mut memo, &task, &others, class, place).await?
        {
            // That robot will take this task; for the next one it is busy.
            others.retain(|other| other.arrival != first);
            state.tasks.stepped_aside();
            continue;
        }
        let lease_until = now + state.tasks.lease();
        let mut tx = state.db.begin_write().await?;
        let max_held = state.tasks.max_held();
        let claimed = tasks::claim(&mut tx, &task.id, robot, now, lease_until, max_held).await?;
        tx.commit().await?;
        if let Some(claimed) = claimed {
            state.feed.committed();
            return Ok(Some(claimed));
        }
        // Another robot was faster: the next one, then.
    }
    Ok(None)
}

/// The robot waiting in line that ranks first for `task`, if it ranks before this one and
/// could run it (its place in line).
async fn someone_else_first(
    state: &AppState,
    memo: &mut Memo,
    task: &TaskRow,
    others: &[Waiter],
    class: Option<&str>,
    place: &Place,
) -> Result<Option<u64>, ApiError> {
    if others.is_empty() {
        return Ok(None);
    }
    let reliable = memo.reliable(state, task).await?;
    let mine = rank(&reliable, class, place.arrival());
    let mut ahead: Vec<&Waiter> = others
        .iter()
        .filter(|other| rank(&reliable, other.class.as_deref(), other.arrival) < mine)
        .filter(|other| targets(task, &other.robot, other.class.as_deref()))
        .collect();
    ahead.sort_by_key(|other| rank(&reliable, other.class.as_deref(), other.arrival));
    for other in ahead {
        if memo.can(state, task, &other.robot).await? {
            return Ok(Some(other.arrival));
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reliable_class_ranks_first_then_the_robot_that_asked_first() {
        let reliable = vec!["pr2".to_owned()];
        let early_el_e = rank(&reliable, Some("el-e"), 1);
        let late_pr2 = rank(&reliable, Some("pr2"), 9);
        let later_el_e = rank(&reliable, Some("el-e"), 5);
        let classless = rank(&reliable, None, 0);
        assert!(late_pr2 < early_el_e);
        assert!(early_el_e < later_el_e);
        assert!(classless < early_el_e, "without a reliable class, arrival decides");
        assert!(late_pr2 < classless);
    }
}
