//! Tasks in the database: what caretakers asked for, who holds each under a lease, how it ended.
//!
//! Every change to a task appends its `task_changed` event in the same transaction, so the feed
//! never misses one and never announces one that did not commit. State changes are single
//! `update … where <the state it must be in> … returning`, so two robots racing for one task
//! cannot both get it.

use serde_json::{Value, json};
use sqlx::{SqliteConnection, SqlitePool};

use crate::clock;
use crate::store::events::{self, EventKind};

/// A robot's lease running out this many times fails the task: a task that keeps killing (or
/// stranding) robots needs a person to look at it.
pub const MAX_ATTEMPTS: i64 = 3;

/// A stored task.
#[derive(Debug, Clone, PartialEq, sqlx::FromRow)]
pub struct TaskRow {
    pub seq: i64,
    pub id: String,
    pub epc: String,
    pub action: String,
    pub robot: Option<String>,
    pub class: Option<String>,
    pub note: Option<String>,
    pub state: String,
    pub created_by: String,
    pub created_at: String,
    pub claimed_by: Option<String>,
    pub lease_until: Option<String>,
    pub attempts: i64,
    /// JSON array of every robot that held the task, in order.
    pub holders: String,
    pub trial: Option<String>,
    pub reason: Option<String>,
    pub updated_at: String,
}

impl TaskRow {
    /// The task as the API returns it.
    pub fn to_json(&self) -> Value {
        json!({
            "id": self.id,
            "epc": self.epc,
            "action": self.action,
            "robot": self.robot,
            "class": self.class,
            "note": self.note,
            "state": self.state,
            "created_by": self.created_by,
            "created_at": self.created_at,
            "claimed_by": self.claimed_by,
            "lease_until": self.lease_until,
            "attempts": self.attempts,
            "holders": self.holders(),
            "trial": self.trial,
            "reason": self.reason,
            "updated_at": self.updated_at,
        })
    }

    /// Every robot that held the task.
    pub fn holders(&self) -> Vec<String> {
        serde_json::from_str(&self.holders).unwrap_or_default()
    }

    /// Whether the task can still change hands or be cancelled.
    pub fn is_open(&self) -> bool {
        matches!(self.state.as_str(), "queued" | "claimed")
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
         lease_until, attempts, holders, trial, reason, updated_at"
    };
}

/// A task as a caretaker asked for it, checked.
#[derive(Debug, Clone)]
pub struct NewTask {
    pub id: String,
    pub epc: String,
    pub action: String,
    pub robot: Option<String>,
    pub class: Option<String>,
    pub note: Option<String>,
    pub created_by: String,
}

async fn announce(tx: &mut SqliteConnection, rows: &[TaskRow]) -> sqlx::Result<()> {
    let data: Vec<Value> = rows.iter().map(TaskRow::announcement).collect();
    events::append_all(tx, EventKind::TaskChanged, &data).await
}

/// Announces the task a statement changed, if it changed one.
async fn announced(
    tx: &mut SqliteConnection,
    row: Option<TaskRow>,
) -> sqlx::Result<Option<TaskRow>> {
    if let Some(row) = &row {
        announce(tx, std::slice::from_ref(row)).await?;
    }
    Ok(row)
}

#[tracing::instrument(skip_all)]
pub async fn create(tx: &mut SqliteConnection, task: &NewTask) -> sqlx::Result<TaskRow> {
    let now = clock::now();
    let row: TaskRow = sqlx::query_as(concat!(
        "insert into tasks (id, epc, action, robot, class, note, state, created_by, created_at, \
         updated_at) values (?, ?, ?, ?, ?, ?, 'queued', ?, ?, ?) returning ",
        columns!()
    ))
    .bind(&task.id)
    .bind(&task.epc)
    .bind(&task.action)
    .bind(&task.robot)
    .bind(&task.class)
    .bind(&task.note)
    .bind(&task.created_by)
    .bind(&now)
    .bind(&now)
    .fetch_one(&mut *tx)
    .await?;
    announce(tx, std::slice::from_ref(&row)).await?;
    Ok(row)
}

#[tracing::instrument(skip_all)]
pub async fn get(pool: &SqlitePool, id: &str) -> sqlx::Result<Option<TaskRow>> {
    sqlx::query_as(concat!("select ", columns!(), " from tasks where id = ?"))
        .bind(id)
        .fetch_optional(pool)
        .await
}

/// Which tasks a list wants.
#[derive(Debug, Default, Clone)]
pub struct TaskFilter {
    pub state: Option<String>,
    pub epc: Option<String>,
    /// Tasks this robot holds, did, or that name it as their target.
    pub robot: Option<String>,
    /// Only what this robot (of this class) may see: what it holds or held, and queued tasks
    /// that target it, its class or anyone.
    pub visible_to: Option<(String, Option<String>)>,
}

/// Up to `limit` tasks before `before` (a `seq`; 0 for the newest), newest first.
#[tracing::instrument(skip_all)]
pub async fn list(
    pool: &SqlitePool,
    filter: &TaskFilter,
    before: i64,
    limit: u32,
) -> sqlx::Result<Vec<TaskRow>> {
    let mut query = sqlx::QueryBuilder::<sqlx::Sqlite>::new(concat!(
        "select ",
        columns!(),
        " from tasks where 1"
    ));
    if before > 0 {
        query.push(" and seq < ").push_bind(before);
    }
    if let Some(state) = &filter.state {
        query.push(" and state = ").push_bind(state.clone());
    }
    if let Some(epc) = &filter.epc {
        query.push(" and epc = ").push_bind(epc.clone());
    }
    if let Some(robot) = &filter.robot {
        query.push(" and (claimed_by = ").push_bind(robot.clone());
        query.push(" or robot = ").push_bind(robot.clone()).push(")");
    }
    if let Some((robot, class)) = &filter.visible_to {
        query.push(" and (claimed_by = ").push_bind(robot.clone());
        query.push(" or exists (select 1 from json_each(holders) where value = ");
        query.push_bind(robot.clone()).push(")");
        query.push(" or (state = 'queued' and (robot is null or robot = ").push_bind(robot.clone());
        query.push(") and (class is null or class = ").push_bind(class.clone()).push(")))");
    }
    query.push(" order by seq desc limit ").push_bind(i64::from(limit));
    query.build_query_as().fetch_all(pool).await
}

/// Tasks `robot` (of `class`) could claim now, oldest first: queued ones, and claimed ones whose
/// lease ran out but that have attempts left, that target it, its class or anyone.
#[tracing::instrument(skip_all)]
pub async fn claimable(
    pool: &SqlitePool,
    robot: &str,
    class: Option<&str>,
    now: &str,
    limit: u32,
) -> sqlx::Result<Vec<TaskRow>> {
    sqlx::query_as(concat!(
        "select ",
        columns!(),
        " from tasks
         where (state = 'queued' or (state = 'claimed' and lease_until <= ?1 and attempts < ?2))
           and (robot is null or robot = ?3) and (class is null or class = ?4)
         order by seq limit ?5"
    ))
    .bind(now)
    .bind(MAX_ATTEMPTS)
    .bind(robot)
    .bind(class)
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await
}

/// Whether any task could be claimed now by some robot: queued, or its lease ran out with
/// attempts left.
pub async fn any_claimable(pool: &SqlitePool, now: &str) -> sqlx::Result<bool> {
    sqlx::query_scalar(
        "select exists (select 1 from tasks where state = 'queued')
             or exists (select 1 from tasks
                        where state = 'claimed' and lease_until <= ?1 and attempts < ?2)",
    )
    .bind(now)
    .bind(MAX_ATTEMPTS)
    .fetch_one(pool)
    .await
}

/// Gives the task to `robot` until `lease_until`, if it is still there for the taking (queued,
/// or its holder's lease ran out with attempts left); `None` when another robot was faster.
#[tracing::instrument(skip_all)]
pub async fn claim(
    tx: &mut SqliteConnection,
    id: &str,
    robot: &str,
    lease_until: &str,
) -> sqlx::Result<Option<TaskRow>> {
    let now = clock::now();
    let row: Option<TaskRow> = sqlx::query_as(concat!(
        "update tasks set state = 'claimed', claimed_by = ?1, lease_until = ?2,
             attempts = attempts + 1, holders = json_insert(holders, '$[#]', ?1), updated_at = ?3
         where id = ?4
           and (state = 'queued' or (state = 'claimed' and lease_until <= ?3 and attempts < ?5))
         returning ",
        columns!()
    ))
    .bind(robot)
    .bind(lease_until)
    .bind(&now)
    .bind(id)
    .bind(MAX_ATTEMPTS)
    .fetch_optional(&mut *tx)
    .await?;
    announced(tx, row).await
}

/// Extends `robot`'s lease on a task it holds and whose lease has not run out.
#[tracing::instrument(skip_all)]
pub async fn extend_lease(
    tx: &mut SqliteConnection,
    id: &str,
    robot: &str,
    lease_until: &str,
) -> sqlx::Result<Option<TaskRow>> {
    // Not announced: only the lease moved, and every holder's heartbeat would flood the feed.
    sqlx::query_as(concat!(
        "update tasks set lease_until = ?1
         where id = ?2 and state = 'claimed' and claimed_by = ?3 and lease_until > ?4
         returning ",
        columns!()
    ))
    .bind(lease_until)
    .bind(id)
    .bind(robot)
    .bind(clock::now())
    .fetch_optional(&mut *tx)
    .await
}

/// Ends a task `robot` holds under a live lease with `trial`: `done` or `failed`.
#[tracing::instrument(skip_all)]
pub async fn finish(
    tx: &mut SqliteConnection,
    id: &str,
    robot: &str,
    trial: &str,
    succeeded: bool,
    reason: Option<&str>,
) -> sqlx::Result<Option<TaskRow>> {
    let now = clock::now();
    let row: Option<TaskRow> = sqlx::query_as(concat!(
        "update tasks set state = ?1, trial = ?2, reason = ?3, lease_until = null, updated_at = ?4
         where id = ?5 and state = 'claimed' and claimed_by = ?6 and lease_until > ?4
         returning ",
        columns!()
    ))
    .bind(if succeeded { "done" } else { "failed" })
    .bind(trial)
    .bind(reason)
    .bind(&now)
    .bind(id)
    .bind(robot)
    .fetch_optional(&mut *tx)
    .await?;
    announced(tx, row).await
}

/// Cancels a queued or claimed task; `None` when it had ended already.
#[tracing::instrument(skip_all)]
pub async fn cancel(
    tx: &mut SqliteConnection,
    id: &str,
    reason: &str,
) -> sqlx::Result<Option<TaskRow>> {
    let rows = cancel_where(tx, false, id, reason).await?;
    Ok(rows.into_iter().next())
}

/// Cancels every open task on a tag (it was archived: no robot may record a trial on it).
#[tracing::instrument(skip_all)]
pub async fn cancel_on_tag(
    tx: &mut SqliteConnection,
    epc: &str,
    reason: &str,
) -> sqlx::Result<Vec<TaskRow>> {
    cancel_where(tx, true, epc, reason).await
}

/// Cancels the open tasks with this id (`by_tag` false) or on this tag (`by_tag` true).
async fn cancel_where(
    tx: &mut SqliteConnection,
    by_tag: bool,
    key: &str,
    reason: &str,
) -> sqlx::Result<Vec<TaskRow>> {
    macro_rules! cancel_by {
        ($column:literal) => {
            concat!(
                "update tasks set state = 'cancelled', reason = ?1, lease_until = null, \
                 updated_at = ?3 where ",
                $column,
                " = ?2 and state in ('queued', 'claimed') returning ",
                columns!()
            )
        };
    }
    let statement = if by_tag { cancel_by!("epc") } else { cancel_by!("id") };
    let rows: Vec<TaskRow> = sqlx::query_as(statement)
        .bind(reason)
        .bind(key)
        .bind(clock::now())
        .fetch_all(&mut *tx)
        .await?;
    announce(tx, &rows).await?;
    Ok(rows)
}

/// Tasks whose holder's lease ran out by `now`: back in the queue, or `failed` once
/// [`MAX_ATTEMPTS`] leases have run out. Returns what changed.
#[tracing::instrument(skip_all)]
pub async fn expire_leases(tx: &mut SqliteConnection, now: &str) -> sqlx::Result<Vec<TaskRow>> {
    let mut changed: Vec<TaskRow> = sqlx::query_as(concat!(
        "update tasks set state = 'failed', lease_until = null, updated_at = ?1,
             reason = 'the lease ran out ' || attempts || ' times (held by ' ||
                 (select group_concat(value, ', ') from json_each(holders)) ||
                 '); no robot finished it'
         where state = 'claimed' and lease_until <= ?1 and attempts >= ?2
         returning ",
        columns!()
    ))
    .bind(now)
    .bind(MAX_ATTEMPTS)
    .fetch_all(&mut *tx)
    .await?;
    let requeued: Vec<TaskRow> = sqlx::query_as(concat!(
        "update tasks set state = 'queued', claimed_by = null, lease_until = null, updated_at = ?1
         where state = 'claimed' and lease_until <= ?1
         returning ",
        columns!()
    ))
    .bind(now)
    .fetch_all(&mut *tx)
    .await?;
    changed.extend(requeued);
    announce(tx, &changed).await?;
    Ok(changed)
}

/// Whether any claimed task's lease runs out by `now` (the sweep's cheap look before it writes).
pub async fn any_lease_expired(pool: &SqlitePool, now: &str) -> sqlx::Result<bool> {
    sqlx::query_scalar(
        "select exists (select 1 from tasks where state = 'claimed' and lease_until <= ?)",
    )
    .bind(now)
    .fetch_one(pool)
    .await
}

/// Moves a tag's tasks to its new EPC (a worn tag replaced); returns how many moved.
pub async fn move_to(conn: &mut SqliteConnection, from: &str, to: &str) -> sqlx::Result<u64> {
    let done = sqlx::query("update tasks set epc = ? where epc = ?")
        .bind(to)
        .bind(from)
        .execute(&mut *conn)
        .await?;
    Ok(done.rows_affected())
}
