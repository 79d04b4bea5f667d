//! A task's lease: the claim, the holder's heartbeat and finish, and the sweep that takes back
//! tasks whose holder went quiet. Each change is one
//! guarded `update … where <the state it must be in> … returning`, so two robots racing for one
//! task cannot both get it, and a lost lease cannot be finished.

use pps_schema::{RobotId, TaskState};
use sqlx::{AnyConnection, AnyPool};
use uuid::Uuid;

use super::{MAX_ATTEMPTS, TaskRow, announce, announced};
use crate::store::columns::{At, Id};
use crate::store::db::Dialect;
use time::OffsetDateTime;

/// The tasks `robot` holds now under a live lease, oldest first.
#[tracing::instrument(skip_all)]
pub async fn held_by(
    pool: &AnyPool,
    robot: &RobotId,
    now: OffsetDateTime,
) -> sqlx::Result<Vec<Uuid>> {
    let held: Vec<Id<Uuid>> = sqlx::query_scalar(
        "select id from tasks where state = 'claimed' and claimed_by = $1 and lease_until > $2
         order by seq",
    )
    .bind(robot.as_str())
    .bind(At(now))
    .fetch_all(pool)
    .await?;
    Ok(held.into_iter().map(|Id(id)| id).collect())
}

/// Gives the task to `robot` from `now` until `lease_until`, if it is still there for the taking (queued,
/// or its holder's lease ran out with attempts left, and not expired) and `robot` holds fewer
/// than `max_held` tasks; `None` when another robot was faster.
#[tracing::instrument(skip_all)]
pub async fn claim(
    tx: &mut AnyConnection,
    id: &Uuid,
    robot: &RobotId,
    now: OffsetDateTime,
    lease_until: OffsetDateTime,
    max_held: usize,
) -> sqlx::Result<Option<TaskRow>> {
    macro_rules! claim_appending {
        ($holders:literal) => {
            concat!(
                "update tasks set state = 'claimed', claimed_by = $1, lease_until = $2,
                     attempts = attempts + 1, holders = ",
                $holders,
                ", updated_at = $3
                 where id = $4
                   and (state = 'queued' or (state = 'claimed' and lease_until <= $3 and attempts < $5))
                   and (expires_at is null or expires_at > $3)
                   and (select count(*) from tasks as held
                        where held.state = 'claimed' and held.claimed_by = $1
                          and held.lease_until > $3) < $6
                 returning ",
                columns!()
            )
        };
    }
    let statement = Dialect::of(tx).pick(
        claim_appending!("json_insert(holders, '$[#]', $1)"),
        claim_appending!("(holders::jsonb || jsonb_build_array($1::text))::text"),
    );
    let row: Option<TaskRow> = sqlx::query_as(statement)
        .bind(robot.as_str())
        .bind(At(lease_until))
        .bind(At(now))
        .bind(id.hyphenated().to_string())
        .bind(MAX_ATTEMPTS)
        .bind(i64::try_from(max_held).unwrap_or(i64::MAX))
        .fetch_optional(&mut *tx)
        .await?;
    announced(tx, row).await
}

/// Extends `robot`'s lease on a task it holds and whose lease has not run out by `now`.
#[tracing::instrument(skip_all)]
pub async fn extend_lease(
    tx: &mut AnyConnection,
    id: &Uuid,
    robot: &RobotId,
    now: OffsetDateTime,
    lease_until: OffsetDateTime,
) -> sqlx::Result<Option<TaskRow>> {
    // Not announced: only the lease moved, and every holder's heartbeat would flood the feed.
    sqlx::query_as(concat!(
        "update tasks set lease_until = $1
         where id = $2 and state = 'claimed' and claimed_by = $3 and lease_until > $4
         returning ",
        columns!()
    ))
    .bind(At(lease_until))
    .bind(id.hyphenated().to_string())
    .bind(robot.as_str())
    .bind(At(now))
    .fetch_optional(&mut *tx)
    .await
}

/// The task `trial` finished, if any: a trial finishes one task.
#[tracing::instrument(skip_all)]
pub async fn finished_with(pool: &AnyPool, trial: &Uuid) -> sqlx::Result<Option<Uuid>> {
    let task: Option<Id<Uuid>> = sqlx::query_scalar("select id from tasks where trial = $1")
        .bind(trial.hyphenated().to_string())
        .fetch_optional(pool)
        .await?;
    Ok(task.map(|Id(id)| id))
}

/// Ends a task `robot` holds under a live lease with `trial`, unless the trial finished
/// another task: `done` or `failed`.
#[tracing::instrument(skip_all)]
pub async fn finish(
    tx: &mut AnyConnection,
    id: &Uuid,
    robot: &RobotId,
    trial: &Uuid,
    succeeded: bool,
    reason: Option<&str>,
    now: OffsetDateTime,
) -> sqlx::Result<Option<TaskRow>> {
    let row: Option<TaskRow> = sqlx::query_as(concat!(
        "update tasks set state = $1, trial = $2, reason = $3, lease_until = null, updated_at = $4
         where id = $5 and state = 'claimed' and claimed_by = $6 and lease_until > $4
           and not exists (select 1 from tasks where trial = $2)
         returning ",
        columns!()
    ))
    .bind(if succeeded { TaskState::Done } else { TaskState::Failed }.as_str())
    .bind(trial.hyphenated().to_string())
    .bind(reason)
    .bind(At(now))
    .bind(id.hyphenated().to_string())
    .bind(robot.as_str())
    .fetch_optional(&mut *tx)
    .await?;
    announced(tx, row).await
}

/// Tasks whose holder's lease ran out by `now`: back in the queue, or `failed` once
/// [`MAX_ATTEMPTS`] leases have run out. Returns what changed.
#[tracing::instrument(skip_all)]
pub async fn expire_leases(
    tx: &mut AnyConnection,
    now: OffsetDateTime,
) -> sqlx::Result<Vec<TaskRow>> {
    macro_rules! fail_naming {
        ($holders:literal) => {
            concat!(
                "update tasks set state = 'failed', lease_until = null, updated_at = $1,
                     reason = 'the lease ran out ' || attempts || ' times (held by ' || ",
                $holders,
                " || '); no robot finished it'
                 where state = 'claimed' and lease_until <= $1 and attempts >= $2
                 returning ",
                columns!()
            )
        };
    }
    let statement = Dialect::of(tx).pick(
        fail_naming!("(select group_concat(value, ', ') from json_each(holders))"),
        fail_naming!(
            "(select string_agg(held.value, ', ') \
              from jsonb_array_elements_text(holders::jsonb) as held(value))"
        ),
    );
    let mut changed: Vec<TaskRow> =
        sqlx::query_as(statement).bind(At(now)).bind(MAX_ATTEMPTS).fetch_all(&mut *tx).await?;
    let requeued: Vec<TaskRow> = sqlx::query_as(concat!(
        "update tasks set state = 'queued', claimed_by = null, lease_until = null, updated_at = $1
         where state = 'claimed' and lease_until <= $1
         returning ",
        columns!()
    ))
    .bind(At(now))
    .fetch_all(&mut *tx)
    .await?;
    changed.extend(requeued);
    announce(tx, &changed).await?;
    Ok(changed)
}
