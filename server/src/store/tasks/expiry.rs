//! Tasks that expire: one no robot took (or finished) by its `expires_at` is cancelled, and
//! its reason says so in words. A task held under a live lease does not expire while the robot
//! works on it; if that robot goes quiet after the expiry, the task expires instead of going
//! back to the queue.

use sqlx::{AnyConnection, AnyPool};
use time::OffsetDateTime;

use super::{TaskRow, announce};
use crate::store::columns::{At, Flag};

/// Whether the sweep has work: a queued task expired, or a lease ran out.
pub async fn any_overdue(pool: &AnyPool, now: OffsetDateTime) -> sqlx::Result<bool> {
    let found: Flag = sqlx::query_scalar(
        "select case when exists (select 1 from tasks where state = 'queued' and expires_at <= $1)
             or exists (select 1 from tasks where state = 'claimed' and lease_until <= $1)
             then 1 else 0 end",
    )
    .bind(At(now))
    .fetch_one(pool)
    .await?;
    Ok(found.into())
}

/// Cancels the tasks that expired by `now`: queued ones, and claimed ones whose lease ran out
/// after their expiry. Returns them.
#[tracing::instrument(skip_all)]
pub async fn expire(tx: &mut AnyConnection, now: OffsetDateTime) -> sqlx::Result<Vec<TaskRow>> {
    let expired: Vec<TaskRow> = sqlx::query_as(concat!(
        "update tasks set state = 'cancelled', lease_until = null, updated_at = $1,
             reason = case when state = 'queued'
                 then 'it expired: no robot took it by ' || expires_at
                 else 'it expired: no robot finished it by ' || expires_at
                      || ', and the lease of the last robot that held it ran out' end
         where expires_at <= $1
           and (state = 'queued' or (state = 'claimed' and lease_until <= $1))
         returning ",
        columns!()
    ))
    .bind(At(now))
    .fetch_all(&mut *tx)
    .await?;
    announce(tx, &expired).await?;
    Ok(expired)
}
