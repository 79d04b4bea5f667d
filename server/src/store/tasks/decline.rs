//! A robot's decline: it cannot do the task and says why. The task goes back to the queue for
//! the other robots, and the declining robot is never offered it again.

use pps_schema::RobotId;
use sqlx::AnyConnection;
use time::OffsetDateTime;
use uuid::Uuid;

use super::{TaskRow, announced};
use crate::store::columns::At;
use crate::store::db::Dialect;

/// Notes that `robot` declined the task for `reason`, with what it said (`detail`), and puts it
/// back in the queue, if it is queued or `robot` holds it and `robot` had not declined it yet;
/// `None` otherwise.
///
/// A claim ended by a decline does not count as an attempt: the robot gave the task back
/// instead of letting its lease run out, and the third lease to run out fails the task.
#[tracing::instrument(skip_all)]
pub async fn decline(
    tx: &mut AnyConnection,
    id: &Uuid,
    robot: &RobotId,
    reason: &str,
    detail: Option<&str>,
    now: OffsetDateTime,
) -> sqlx::Result<Option<TaskRow>> {
    macro_rules! decline_appending {
        ($appended:literal, $declined_before:literal) => {
            concat!(
                "update tasks set declines = ",
                $appended,
                ", state = 'queued', claimed_by = null, lease_until = null,
                     attempts = case when state = 'claimed' then attempts - 1 else attempts end,
                     updated_at = $3
                 where id = $4
                   and (state = 'queued' or (state = 'claimed' and claimed_by = $1))
                   and not exists (",
                $declined_before,
                ") returning ",
                columns!()
            )
        };
    }
    let statement = Dialect::of(tx).pick(
        decline_appending!(
            "json_insert(declines, '$[#]', json_object('robot', $1, 'reason', $2, 'at', $3, 'detail', $5))",
            "select 1 from json_each(declines) where json_extract(value, '$.robot') = $1"
        ),
        decline_appending!(
            "(declines::jsonb || jsonb_build_array(jsonb_build_object(\
                 'robot', $1::text, 'reason', $2::text, 'at', $3::text, 'detail', $5::text)))::text",
            "select 1 from jsonb_array_elements(declines::jsonb) as declined(value) \
             where declined.value ->> 'robot' = $1"
        ),
    );
    let row: Option<TaskRow> = sqlx::query_as(statement)
        .bind(robot.as_str())
        .bind(reason)
        .bind(At(now))
        .bind(id.hyphenated().to_string())
        .bind(detail)
        .fetch_optional(&mut *tx)
        .await?;
    announced(tx, row).await
}
