//! What the registry learned from trials: learned parameter values and the last reliability
//! verdict per action and robot class.

use pps_schema::Epc;
use sqlx::{AnyConnection, AnyPool};

use crate::store::columns::{At, MaybeFlag};
use crate::store::db::Dialect;
use crate::store::trial_counts::{GroupKey, groups_parameter};

use crate::clock;

/// A value learned from trials, addressed by its JSON pointer in the entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Learned {
    pub pointer: String,
    pub value: f64,
}

/// How the learned tables key a robot class: `""` for robots without one (a key column cannot
/// be null).
fn class_key(robot_class: Option<&str>) -> &str {
    robot_class.unwrap_or("")
}

/// Learned values for one tag and robot class (`None` for robots without one).
pub async fn learned_for(
    pool: &AnyPool,
    epc: &Epc,
    robot_class: Option<&str>,
) -> sqlx::Result<Vec<Learned>> {
    let rows: Vec<(String, f64)> = sqlx::query_as(
        "select pointer, value from learned_values where epc = $1 and robot_class = $2 order by pointer",
    )
    .bind(epc.as_hex())
    .bind(class_key(robot_class))
    .fetch_all(pool)
    .await?;
    Ok(rows.into_iter().map(|(pointer, value)| Learned { pointer, value }).collect())
}

/// Every learned value of a tag: (robot class, pointer, value, trials).
pub async fn learned_all(
    pool: &AnyPool,
    epc: &Epc,
) -> sqlx::Result<Vec<(Option<String>, String, f64, i64)>> {
    let rows: Vec<(String, String, f64, i64)> = sqlx::query_as(
        "select robot_class, pointer, value, trials from learned_values where epc = $1 order by robot_class, pointer",
    )
    .bind(epc.as_hex())
    .fetch_all(pool)
    .await?;
    Ok(rows
        .into_iter()
        .map(|(class, pointer, value, trials)| {
            (Some(class).filter(|class| !class.is_empty()), pointer, value, trials)
        })
        .collect())
}

/// Stores a learned value; true when it differs from what was stored.
pub async fn store_learned(
    conn: &mut AnyConnection,
    epc: &Epc,
    robot_class: Option<&str>,
    pointer: &str,
    value: f64,
    trials: i64,
) -> sqlx::Result<bool> {
    let previous: Option<f64> = sqlx::query_scalar(
        "select value from learned_values where epc = $1 and robot_class = $2 and pointer = $3",
    )
    .bind(epc.as_hex())
    .bind(class_key(robot_class))
    .bind(pointer)
    .fetch_optional(&mut *conn)
    .await?;
    sqlx::query(
        "insert into learned_values (epc, robot_class, pointer, value, trials, updated_at)
         values ($1, $2, $3, $4, $5, $6)
         on conflict (epc, robot_class, pointer) do update set value = excluded.value,
             trials = excluded.trials, updated_at = excluded.updated_at",
    )
    .bind(epc.as_hex())
    .bind(class_key(robot_class))
    .bind(pointer)
    .bind(value)
    .bind(trials)
    .bind(At(clock::recorded_now()))
    .execute(conn)
    .await?;
    Ok(previous != Some(value))
}

/// Drops a learned value no trial supports any more; true when one was dropped.
pub async fn forget_learned(
    conn: &mut AnyConnection,
    epc: &Epc,
    robot_class: Option<&str>,
    pointer: &str,
) -> sqlx::Result<bool> {
    let done = sqlx::query(
        "delete from learned_values where epc = $1 and robot_class = $2 and pointer = $3",
    )
    .bind(epc.as_hex())
    .bind(class_key(robot_class))
    .bind(pointer)
    .execute(conn)
    .await?;
    Ok(done.rows_affected() > 0)
}

/// The stored reliability verdict of each group, `None` where none was ever made, in the
/// order of `groups`.
pub async fn reliabilities(
    conn: &mut AnyConnection,
    groups: &[GroupKey<'_>],
) -> sqlx::Result<Vec<Option<bool>>> {
    let verdicts: Vec<MaybeFlag> = sqlx::query_scalar(Dialect::of(conn).pick(
        "select (select reliable from reliability
                 where epc = json_extract(g.value, '$[0]') and action = json_extract(g.value, '$[1]')
                   and robot_class = coalesce(json_extract(g.value, '$[2]'), ''))
         from json_each($1) as g order by g.key",
        "select reliability.reliable
         from jsonb_array_elements($1::jsonb) with ordinality as g(value, ord)
         left join reliability on reliability.epc = g.value->>0
              and reliability.action = g.value->>1
              and reliability.robot_class = coalesce(g.value->>2, '')
         order by g.ord",
    ))
    .bind(groups_parameter(groups))
    .fetch_all(conn)
    .await?;
    Ok(verdicts.into_iter().map(Option::from).collect())
}

/// Robot classes whose trials made `action` on `epc` reliable (the stats' reliable flag).
pub async fn reliable_classes(
    pool: &AnyPool,
    epc: &Epc,
    action: &str,
) -> sqlx::Result<Vec<String>> {
    sqlx::query_scalar(
        "select robot_class from reliability where epc = $1 and action = $2 and reliable = 1",
    )
    .bind(epc.as_hex())
    .bind(action)
    .fetch_all(pool)
    .await
}

pub async fn store_reliability(
    conn: &mut AnyConnection,
    epc: &Epc,
    action: &str,
    robot_class: Option<&str>,
    reliable: bool,
) -> sqlx::Result<()> {
    sqlx::query(
        "insert into reliability (epc, action, robot_class, reliable) values ($1, $2, $3, $4)
         on conflict (epc, action, robot_class) do update set reliable = excluded.reliable",
    )
    .bind(epc.as_hex())
    .bind(action)
    .bind(class_key(robot_class))
    .bind(i64::from(reliable))
    .execute(conn)
    .await?;
    Ok(())
}

/// Moves learned values and verdicts of a retagged tag to its new EPC.
pub async fn move_to(conn: &mut AnyConnection, from: &Epc, to: &Epc) -> sqlx::Result<()> {
    for statement in [
        "update learned_values set epc = $1 where epc = $2",
        "update reliability set epc = $1 where epc = $2",
        "update learned_colours set epc = $1 where epc = $2",
        "update learned_sizes set epc = $1 where epc = $2",
    ] {
        sqlx::query(statement).bind(to.as_hex()).bind(from.as_hex()).execute(&mut *conn).await?;
    }
    Ok(())
}
