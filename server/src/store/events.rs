//! The change feed's rows: appended in the same transaction as the change they describe.

use serde::Serialize;
use serde_json::Value;
use sqlx::{AnyConnection, AnyPool};

use crate::clock;
use crate::store::columns::At;
use crate::store::placeholders;

/// What changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    TagChanged,
    TagArchived,
    TagRetagged,
    TrialRecorded,
    TrialUpdated,
    RobotChanged,
    InboxChanged,
    ReliabilityChanged,
    /// A robot class's trials taught a tag new values: its robots' effective entries changed.
    LearnedChanged,
    /// A task was asked for, claimed, requeued, finished or cancelled.
    TaskChanged,
}

impl EventKind {
    pub const ALL: [EventKind; 10] = [
        Self::TagChanged,
        Self::TagArchived,
        Self::TagRetagged,
        Self::TrialRecorded,
        Self::TrialUpdated,
        Self::RobotChanged,
        Self::InboxChanged,
        Self::ReliabilityChanged,
        Self::LearnedChanged,
        Self::TaskChanged,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::TagChanged => "tag_changed",
            Self::TagArchived => "tag_archived",
            Self::TagRetagged => "tag_retagged",
            Self::TrialRecorded => "trial_recorded",
            Self::TrialUpdated => "trial_updated",
            Self::RobotChanged => "robot_changed",
            Self::InboxChanged => "inbox_changed",
            Self::ReliabilityChanged => "reliability_changed",
            Self::LearnedChanged => "learned_changed",
            Self::TaskChanged => "task_changed",
        }
    }

    pub fn parse(text: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|kind| kind.as_str() == text)
    }

    /// Whether the event changes what robots read for a tag (as opposed to trials, robots, the
    /// inbox): every robot sees these.
    pub fn is_tag_event(self) -> bool {
        matches!(
            self,
            Self::TagChanged | Self::TagArchived | Self::TagRetagged | Self::LearnedChanged
        )
    }
}

/// One stored event.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    pub id: i64,
    pub kind: EventKind,
    pub data: Value,
}

/// Appends an event inside the caller's transaction.
pub async fn append(tx: &mut AnyConnection, kind: EventKind, data: Value) -> sqlx::Result<i64> {
    let id = sqlx::query_scalar(
        "insert into events (kind, data, created_at) values ($1, $2, $3) returning id",
    )
    .bind(kind.as_str())
    .bind(data.to_string())
    .bind(At(clock::recorded_now()))
    .fetch_one(&mut *tx)
    .await?;
    Ok(id)
}

/// Appends one event of `kind` per item of `data`, in order, with one statement.
pub async fn append_all(
    tx: &mut AnyConnection,
    kind: EventKind,
    data: &[Value],
) -> sqlx::Result<()> {
    let now = At(clock::recorded_now());
    for chunk in data.chunks(500) {
        let statement = format!(
            "insert into events (kind, data, created_at) values {}",
            placeholders::rows(chunk.len(), 3)
        );
        let mut insert = sqlx::query(sqlx::AssertSqlSafe(statement));
        for item in chunk {
            insert = insert.bind(kind.as_str()).bind(item.to_string()).bind(now);
        }
        insert.execute(&mut *tx).await?;
    }
    Ok(())
}

/// Events with ids above `after`, oldest first.
#[tracing::instrument(skip_all)]
pub async fn after(pool: &AnyPool, after: i64, limit: u32) -> sqlx::Result<Vec<Event>> {
    let rows: Vec<(i64, String, String)> =
        sqlx::query_as("select id, kind, data from events where id > $1 order by id limit $2")
            .bind(after)
            .bind(i64::from(limit))
            .fetch_all(pool)
            .await?;
    Ok(rows
        .into_iter()
        .filter_map(|(id, kind, data)| {
            Some(Event {
                id,
                kind: EventKind::parse(&kind)?,
                data: serde_json::from_str(&data).ok()?,
            })
        })
        .collect())
}

/// Events the feed keeps, at most: enough for any client to resume after a long outage (a
/// client that falls further behind reloads anyway), bounded so the table cannot grow forever.
pub const KEEP: i64 = 100_000;

/// Drops events older than the newest [`KEEP`]; returns how many went.
#[tracing::instrument(skip_all)]
pub async fn prune(tx: &mut AnyConnection) -> sqlx::Result<u64> {
    let done = sqlx::query("delete from events where id <= (select max(id) from events) - $1")
        .bind(KEEP)
        .execute(&mut *tx)
        .await?;
    Ok(done.rows_affected())
}

/// The newest event's id, 0 when there are none.
pub async fn last_id(pool: &AnyPool) -> sqlx::Result<i64> {
    sqlx::query_scalar("select coalesce(max(id), 0) from events").fetch_one(pool).await
}
