//! A checked task request queued for the robots; asked by the bridge, only while it holds its
//! lease.

use uuid::Uuid;

use super::request::TaskRequest;
use crate::error::ApiError;
use crate::state::AppState;
use crate::store::home_assistant;
use crate::store::tasks::{self, NewTask, TaskRow};

/// Queues the task `asker` asked for: checked as every request is, stored with its event,
/// and the robots waiting for work woken. The web UI's "Ask a robot" and the Home Assistant
/// bridge's buttons both come here. With `bridge_lease`, the task is stored only while that
/// holder still holds the bridge's lease, checked in the same write transaction: a replica
/// that lost the lease never turns a press into a second task.
pub(crate) async fn ask(
    state: &AppState,
    asked: TaskRequest,
    asker: &str,
    bridge_lease: Option<&str>,
) -> Result<TaskRow, ApiError> {
    asked.check(state).await?;
    let task = NewTask {
        id: Uuid::new_v4(),
        epc: asked.epc,
        action: asked.action,
        robot: asked.robot,
        class: asked.class,
        note: asked.note,
        created_by: asker.to_owned(),
        expires_at: asked.expires_at,
    };
    let now = state.clock.now();
    let mut tx = state.db.begin_write().await?;
    if let Some(holder) = bridge_lease
        && !home_assistant::holds_lease(&mut tx, holder, now).await?
    {
        return Err(ApiError::Conflict(
            "this replica no longer runs the Home Assistant bridge; another one took it over"
                .into(),
        ));
    }
    let row = tasks::create(&mut tx, &task, now).await?;
    tx.commit().await?;
    // The feed's pump wakes the robots waiting for a task.
    state.feed.committed();
    Ok(row)
}
