//! Tasks in the database: what caretakers asked for, who holds each under a lease, how it ended.
//!
//! Every change to a task appends its `task_changed` event in the same transaction, so the feed
//! never misses one and never announces one that did not commit. Here: the row, asking for a
//! task, reading and listing tasks, cancelling; the lease (claim, heartbeat, finish, the sweep)
//! is `lease.rs`, a robot's decline `decline.rs`.

use pps_schema::{Epc, RobotId, TaskState};
use serde_json::{Value, json};
use sqlx::{AnyConnection, AnyPool};
use uuid::Uuid;

use time::OffsetDateTime;

use crate::clock;
use crate::store::columns::{At, Id, MaybeAt, MaybeId};
use crate::store::db::Dialect;
use crate::store::events::{self, EventKind};

/// A robot's lease running out this many times fails the task: a task that keeps killing (or
/// stranding) robots needs a person to look at it.
pub const MAX_ATTEMPTS: i64 = 3;

/// A stored task.
#[derive(Debug, Clone, PartialEq, sqlx::FromRow)]
pub struct TaskRow {
    pub seq: i64,
    #[sqlx(try_from = "Id<Uuid>")]
    pub id: Uuid,
    #[sqlx(try_from = "Id<Epc>")]
    pub epc: Epc,
    pub action: String,
    #[sqlx(try_from = "MaybeId<RobotId>")]
    pub robot: Option<RobotId>,
    pub class: Option<String>,
    pub note: Option<String>,
    #[sqlx(try_from = "Id<TaskState>")]
    pub state: TaskState,
    pub created_by: String,
    #[sqlx(try_from = "At")]
    pub created_at: OffsetDateTime,
    #[sqlx(try_from = "MaybeId<RobotId>")]
    pub claimed_by: Option<RobotId>,
    #[sqlx(try_from = "MaybeAt")]
    pub lease_until: Option<OffsetDateTime>,
    pub attempts: i64,
    /// JSON array of every robot that held the task, in order.
    pub holders: String,
    #[sqlx(try_from = "MaybeId<Uuid>")]
    pub trial: Option<Uuid>,
    pub reason: Option<String>,
    #[sqlx(try_from = "At")]
    pub updated_at: OffsetDateTime,
    /// JSON array of every decline, in order: `{"robot", "reason", "at"}`.
    pub declines: String,
    /// When it expires unless a robot took it; `None` for never.
    #[sqlx(try_from = "MaybeAt")]
    pub expires_at: Option<OffsetDateTime>,
}

/// A robot's word that it cannot do a task, and why.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Decline {
    pub robot: RobotId,
    /// Why, in a caretaker's words.
    pub reason: String,
    /// What the robot itself said, for whoever looks further.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub detail: Option<String>,
    #[serde(with = "clock::stored")]
    pub at: OffsetDateTime,
}

impl TaskRow {
    /// Every robot that declined the task, with its reason, in order.
    pub fn declined(&self) -> Vec<Decline> {
        serde_json::from_str(&self.declines).unwrap_or_default()
    }

    /// Whether `robot` declined the task: it is never offered to it again.
    pub fn declined_by(&self, robot: &RobotId) -> bool {
        self.declined().iter().any(|decline| &decline.robot == robot)
    }

    /// Every robot that held the task.
    pub fn holders(&self) -> Vec<RobotId> {
        serde_json::from_str(&self.holders).unwrap_or_default()
    }

    /// Whether the task ended because it expired before a robot took it (or finished it).
    pub fn expired(&self) -> bool {
        self.state == TaskState::Cancelled
            && self.expires_at.is_some_and(|at| at <= self.updated_at)
    }

    /// Whether the task can still change hands or be cancelled.
    pub fn is_open(&self) -> bool {
        self.state.is_open()
    }

    /// The event announcing this task as it is now.
    fn announcement(&self) -> Value {
        json!({
            "task": self.id, "epc": self.epc, "action": self.action, "state": self.state,
            "claimed_by": self.claimed_by, "trial": self.trial,
        })
    }
}

/// The columns of a [`TaskRow`], as a literal so statements stay `&'static str`.
macro_rules! columns {
    () => {
        "seq, id, epc, action, robot, class, note, state, created_by, created_at, claimed_by, \
         lease_until, attempts, holders, trial, reason, updated_at, declines, expires_at"
    };
}

mod decline;
mod expiry;
mod lease;
mod offer;

pub use decline::decline;
pub use expiry::{any_overdue, expire};
pub use lease::{claim, expire_leases, extend_lease, finish, finished_with, held_by};
pub use offer::{claimable, claimable_kinds};

/// A task as a caretaker asked for it, checked.
#[derive(Debug, Clone)]
pub struct NewTask {
    pub id: Uuid,
    pub epc: Epc,
    pub action: String,
    pub robot: Option<RobotId>,
    pub class: Option<String>,
    pub note: Option<String>,
    pub created_by: String,
    /// When it expires unless a robot took it.
    pub expires_at: OffsetDateTime,
}

async fn announce(tx: &mut AnyConnection, rows: &[TaskRow]) -> sqlx::Result<()> {
    let data: Vec<Value> = rows.iter().map(TaskRow::announcement).collect();
    events::append_all(tx, EventKind::TaskChanged, &data).await
}

/// Announces the task a statement changed, if it changed one.
async fn announced(tx: &mut AnyConnection, row: Option<TaskRow>) -> sqlx::Result<Option<TaskRow>> {
    if let Some(row) = &row {
        announce(tx, std::slice::from_ref(row)).await?;
    }
    Ok(row)
}

#[tracing::instrument(skip_all)]
pub async fn create(
    tx: &mut AnyConnection,
    task: &NewTask,
    now: OffsetDateTime,
) -> sqlx::Result<TaskRow> {
    let row: TaskRow = sqlx::query_as(concat!(
        "insert into tasks (id, epc, action, robot, class, note, state, created_by, created_at, \
         updated_at, expires_at) values ($1, $2, $3, $4, $5, $6, 'queued', $7, $8, $9, $10) \
         returning ",
        columns!()
    ))
    .bind(task.id.hyphenated().to_string())
    .bind(task.epc.as_hex())
    .bind(&task.action)
    .bind(task.robot.as_ref().map(RobotId::as_str))
    .bind(&task.class)
    .bind(&task.note)
    .bind(&task.created_by)
    .bind(At(now))
    .bind(At(now))
    .bind(At(task.expires_at))
    .fetch_one(&mut *tx)
    .await?;
    announce(tx, std::slice::from_ref(&row)).await?;
    Ok(row)
}

#[tracing::instrument(skip_all)]
pub async fn get(pool: &AnyPool, id: &Uuid) -> sqlx::Result<Option<TaskRow>> {
    sqlx::query_as(concat!("select ", columns!(), " from tasks where id = $1"))
        .bind(id.hyphenated().to_string())
        .fetch_optional(pool)
        .await
}

/// Which tasks a list wants.
#[derive(Debug, Default, Clone)]
pub struct TaskFilter {
    pub state: Option<TaskState>,
    pub epc: Option<Epc>,
    /// Tasks this robot holds, did, or that name it as their target.
    pub robot: Option<RobotId>,
    /// Only what this robot (of this class) may see: what it holds or held, and queued tasks
    /// that target it, its class or anyone.
    pub visible_to: Option<(RobotId, Option<String>)>,
}

/// Up to `limit` tasks before `before` (a `seq`; 0 for the newest), newest first.
#[tracing::instrument(skip_all)]
pub async fn list(
    pool: &AnyPool,
    filter: &TaskFilter,
    before: i64,
    limit: u32,
) -> sqlx::Result<Vec<TaskRow>> {
    // A filter left out is a null parameter, so the statement stays one static text.
    macro_rules! list_where_held {
        ($held:literal) => {
            concat!(
                "select ",
                columns!(),
                " from tasks
                 where ($1 = 0 or seq < $1)
                   and (cast($2 as text) is null or state = $2)
                   and (cast($3 as text) is null or epc = $3)
                   and (cast($4 as text) is null or claimed_by = $4 or robot = $4)
                   and (cast($5 as text) is null or claimed_by = $5 or ",
                $held,
                "      or (state = 'queued' and (robot is null or robot = $5)
                           and (class is null or class = $6)))
                 order by seq desc limit $7"
            )
        };
    }
    let statement = Dialect::of_pool(pool).pick(
        list_where_held!("exists (select 1 from json_each(holders) where value = $5)"),
        list_where_held!(
            "exists (select 1 from jsonb_array_elements_text(holders::jsonb) as held(value) \
             where held.value = $5)"
        ),
    );
    let (visible_robot, visible_class) = match &filter.visible_to {
        Some((robot, class)) => (Some(robot.as_str()), class.as_deref()),
        None => (None, None),
    };
    sqlx::query_as(statement)
        .bind(before)
        .bind(filter.state.map(TaskState::as_str))
        .bind(filter.epc.as_ref().map(Epc::as_hex))
        .bind(filter.robot.as_ref().map(RobotId::as_str))
        .bind(visible_robot)
        .bind(visible_class)
        .bind(i64::from(limit))
        .fetch_all(pool)
        .await
}

/// Cancels a queued or claimed task; `None` when it had ended already.
#[tracing::instrument(skip_all)]
pub async fn cancel(
    tx: &mut AnyConnection,
    id: &Uuid,
    reason: &str,
    now: OffsetDateTime,
) -> sqlx::Result<Option<TaskRow>> {
    let rows = cancel_where(tx, false, &id.hyphenated().to_string(), reason, now).await?;
    Ok(rows.into_iter().next())
}

/// Cancels every open task on a tag (it was archived: no robot may record a trial on it).
#[tracing::instrument(skip_all)]
pub async fn cancel_on_tag(
    tx: &mut AnyConnection,
    epc: &Epc,
    reason: &str,
    now: OffsetDateTime,
) -> sqlx::Result<Vec<TaskRow>> {
    cancel_where(tx, true, epc.as_hex(), reason, now).await
}

/// Cancels the open tasks with this id (`by_tag` false) or on this tag (`by_tag` true).
async fn cancel_where(
    tx: &mut AnyConnection,
    by_tag: bool,
    key: &str,
    reason: &str,
    now: OffsetDateTime,
) -> sqlx::Result<Vec<TaskRow>> {
    macro_rules! cancel_by {
        ($column:literal) => {
            concat!(
                "update tasks set state = 'cancelled', reason = $1, lease_until = null, \
                 updated_at = $3 where ",
                $column,
                " = $2 and state in ('queued', 'claimed') returning ",
                columns!()
            )
        };
    }
    let statement = if by_tag { cancel_by!("epc") } else { cancel_by!("id") };
    let rows: Vec<TaskRow> =
        sqlx::query_as(statement).bind(reason).bind(key).bind(At(now)).fetch_all(&mut *tx).await?;
    announce(tx, &rows).await?;
    Ok(rows)
}

/// Moves a tag's tasks to its new EPC (a worn tag replaced); returns how many moved.
pub async fn move_to(conn: &mut AnyConnection, from: &Epc, to: &Epc) -> sqlx::Result<u64> {
    let done = sqlx::query("update tasks set epc = $1 where epc = $2")
        .bind(to.as_hex())
        .bind(from.as_hex())
        .execute(&mut *conn)
        .await?;
    Ok(done.rows_affected())
}
