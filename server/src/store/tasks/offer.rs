//! Which tasks a robot could claim now, read so that what it cannot do never hides what it can:
//! first the kinds of task (tag and action) open to it, then, among the kinds it can do, the
//! oldest tasks. However many tasks lie ahead that it cannot do, the second read skips them in
//! the database.

use pps_schema::{Epc, RobotId};
use sqlx::AnyPool;
use time::OffsetDateTime;

use super::{MAX_ATTEMPTS, TaskRow};
use crate::store::columns::{At, Id};
use crate::store::db::Dialect;

/// The tasks open to a robot, as a `where` clause: queued ones, and claimed ones whose lease
/// ran out but that have attempts left, not expired, that target it (`$3`), its class (`$4`)
/// or anyone, and that it has not declined. `$1` is now, `$2` the attempts a task may have.
macro_rules! open_to_robot {
    ($declined:literal) => {
        concat!(
            " where (state = 'queued' or (state = 'claimed' and lease_until <= $1 and attempts < $2))
                and (expires_at is null or expires_at > $1)
                and (robot is null or robot = $3) and (class is null or class = $4)
                and not exists (",
            $declined,
            ")"
        )
    };
}

/// A statement on the open tasks, for SQLite and for PostgreSQL.
macro_rules! per_dialect {
    ($sqlite:ident, $postgres:ident) => {
        (
            $sqlite!(open_to_robot!(
                "select 1 from json_each(declines) where json_extract(value, '$.robot') = $3"
            )),
            $postgres!(open_to_robot!(
                "select 1 from jsonb_array_elements(declines::jsonb) as declined(value) \
                 where declined.value ->> 'robot' = $3"
            )),
        )
    };
}

/// The tags and actions of the tasks `robot` (of `class`) could claim now, once each.
#[tracing::instrument(skip_all)]
pub async fn claimable_kinds(
    pool: &AnyPool,
    robot: &RobotId,
    class: Option<&str>,
    now: OffsetDateTime,
) -> sqlx::Result<Vec<(Epc, String)>> {
    macro_rules! kinds {
        ($where:expr) => {
            concat!("select epc, action from tasks", $where, " group by epc, action")
        };
    }
    let (sqlite, postgres) = per_dialect!(kinds, kinds);
    let rows: Vec<(Id<Epc>, String)> =
        sqlx::query_as(Dialect::of_pool(pool).pick(sqlite, postgres))
            .bind(At(now))
            .bind(MAX_ATTEMPTS)
            .bind(robot.as_str())
            .bind(class)
            .fetch_all(pool)
            .await?;
    Ok(rows.into_iter().map(|(Id(epc), action)| (epc, action)).collect())
}

/// Up to `limit` tasks `robot` (of `class`) could claim now, oldest first, of the `kinds` (tag
/// and action) it can do.
#[tracing::instrument(skip_all)]
pub async fn claimable(
    pool: &AnyPool,
    robot: &RobotId,
    class: Option<&str>,
    now: OffsetDateTime,
    kinds: &[(Epc, String)],
    limit: u32,
) -> sqlx::Result<Vec<TaskRow>> {
    if kinds.is_empty() {
        return Ok(Vec::new());
    }
    // A hex EPC holds no colon, so "EPC:action" names one kind unambiguously.
    macro_rules! oldest {
        ($where:expr) => {
            concat!(
                "select ",
                columns!(),
                " from tasks",
                $where,
                " and epc || ':' || action in (select value from json_each($5))
                 order by seq limit $6"
            )
        };
    }
    macro_rules! oldest_postgres {
        ($where:expr) => {
            concat!(
                "select ",
                columns!(),
                " from tasks",
                $where,
                " and epc || ':' || action in (select jsonb_array_elements_text($5::jsonb))
                 order by seq limit $6"
            )
        };
    }
    let (sqlite, postgres) = per_dialect!(oldest, oldest_postgres);
    let kinds: Vec<String> =
        kinds.iter().map(|(epc, action)| format!("{}:{action}", epc.as_hex())).collect();
    sqlx::query_as(Dialect::of_pool(pool).pick(sqlite, postgres))
        .bind(At(now))
        .bind(MAX_ATTEMPTS)
        .bind(robot.as_str())
        .bind(class)
        .bind(serde_json::to_string(&kinds).unwrap_or_default())
        .bind(i64::from(limit))
        .fetch_all(pool)
        .await
}
