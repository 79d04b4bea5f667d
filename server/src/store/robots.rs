//! The robot registry: who the robots are, their class, capabilities and limits.

use pps_schema::RobotId;
use serde_json::{Value, json};
use sqlx::AnyPool;
use time::OffsetDateTime;

use crate::store::columns::{At, Flag, Id};

use crate::clock;
use crate::store::db::Db;
use crate::store::events::{self, EventKind};

/// A robot as the registry knows it.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredRobot {
    pub id: RobotId,
    pub class: Option<String>,
    /// The robot as PUT; `None` for a robot known only from its token, not yet registered.
    pub document: Option<Value>,
}

/// What a PUT did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RobotWrite {
    Created,
    Replaced,
    Unchanged,
}

type Row = (Id<RobotId>, Option<String>, Option<String>);

fn from_row((id, class, document): Row) -> StoredRobot {
    StoredRobot {
        id: id.into(),
        class,
        document: document.and_then(|d| serde_json::from_str(&d).ok()),
    }
}

#[tracing::instrument(skip_all)]
pub async fn get(pool: &AnyPool, id: &RobotId) -> sqlx::Result<Option<StoredRobot>> {
    let row: Option<Row> = sqlx::query_as("select id, class, document from robots where id = $1")
        .bind(id.as_str())
        .fetch_optional(pool)
        .await?;
    if let Some(row) = row {
        return Ok(Some(from_row(row)));
    }
    let has_token: Flag = sqlx::query_scalar(
        "select case when exists (select 1 from tokens where robot_id = $1 and revoked_at is null)
                then 1 else 0 end",
    )
    .bind(id.as_str())
    .fetch_one(pool)
    .await?;
    Ok(bool::from(has_token).then(|| StoredRobot { id: id.clone(), class: None, document: None }))
}

/// The class of the robot `id`; `None` when it has none or is not registered.
pub async fn class_of(
    conn: &mut sqlx::AnyConnection,
    id: &RobotId,
) -> sqlx::Result<Option<String>> {
    let class: Option<Option<String>> =
        sqlx::query_scalar("select class from robots where id = $1")
            .bind(id.as_str())
            .fetch_optional(conn)
            .await?;
    Ok(class.flatten())
}

/// Registered robots and robots that only have a token, in id order after `after`.
#[tracing::instrument(skip_all)]
pub async fn list(
    pool: &AnyPool,
    after: Option<&str>,
    limit: u32,
) -> sqlx::Result<Vec<StoredRobot>> {
    let rows: Vec<Row> = sqlx::query_as(
        "select id, class, document from (
             select id, class, document from robots
             union
             select distinct robot_id, null, null from tokens
             where robot_id is not null and revoked_at is null
               and robot_id not in (select id from robots)) as known
         where (cast($1 as text) is null or id > $1) order by id limit $2",
    )
    .bind(after)
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await?;
    Ok(rows.into_iter().map(from_row).collect())
}

/// The registered robots of one class, in id order.
#[tracing::instrument(skip_all)]
pub async fn of_class(pool: &AnyPool, class: &str) -> sqlx::Result<Vec<StoredRobot>> {
    let rows: Vec<Row> =
        sqlx::query_as("select id, class, document from robots where class = $1 order by id")
            .bind(class)
            .fetch_all(pool)
            .await?;
    Ok(rows.into_iter().map(from_row).collect())
}

/// Registers or changes a robot; the same document again changes nothing.
#[tracing::instrument(skip_all, fields(robot = id.as_str()))]
pub async fn put(db: &Db, id: &RobotId, document: &Value, by: &str) -> sqlx::Result<RobotWrite> {
    let mut tx = db.begin_write().await?;
    let current: Option<String> = sqlx::query_scalar("select document from robots where id = $1")
        .bind(id.as_str())
        .fetch_optional(&mut *tx)
        .await?;
    let current: Option<Value> = current.and_then(|d| serde_json::from_str(&d).ok());
    if current.as_ref() == Some(document) {
        return Ok(RobotWrite::Unchanged);
    }
    let class = document.get("class").and_then(Value::as_str);
    sqlx::query(
        "insert into robots (id, class, document, updated_at, updated_by) values ($1, $2, $3, $4, $5)
         on conflict (id) do update set class = excluded.class, document = excluded.document,
             updated_at = excluded.updated_at, updated_by = excluded.updated_by",
    )
    .bind(id.as_str())
    .bind(class)
    .bind(document.to_string())
    .bind(At(clock::recorded_now()))
    .bind(by)
    .execute(&mut *tx)
    .await?;
    events::append(&mut tx, EventKind::RobotChanged, json!({ "robot": id.as_str() })).await?;
    tx.commit().await?;
    Ok(if current.is_some() { RobotWrite::Replaced } else { RobotWrite::Created })
}

/// When each robot was last seen, as last flushed.
pub async fn presence(pool: &AnyPool) -> sqlx::Result<Vec<(String, OffsetDateTime)>> {
    let rows: Vec<(String, At)> =
        sqlx::query_as("select robot, last_seen from robot_presence").fetch_all(pool).await?;
    Ok(rows.into_iter().map(|(robot, At(at))| (robot, at)).collect())
}

/// Stores last-seen times gathered in memory.
pub async fn record_presence(db: &Db, seen: &[(String, OffsetDateTime)]) -> sqlx::Result<()> {
    let mut tx = db.begin_write().await?;
    for (robot, at) in seen {
        sqlx::query(
            "insert into robot_presence (robot, last_seen) values ($1, $2)
             on conflict (robot) do update set last_seen = case
                 when excluded.last_seen > robot_presence.last_seen then excluded.last_seen
                 else robot_presence.last_seen end",
        )
        .bind(robot)
        .bind(At(*at))
        .execute(&mut *tx)
        .await?;
    }
    tx.commit().await
}
