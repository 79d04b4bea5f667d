//! What a tag's trials add up to, for its stats and for learning: counts per action and robot
//! class, the latest outcomes a reliable flag is judged on, and the latest measurements a value
//! is learned from. Each counts only the purposes it is asked to (real use by default).

use pps_schema::Epc;
use serde_json::{Value, json};
use sqlx::{AnyConnection, AnyPool};

use crate::store::db::Dialect;
use crate::trials::counted_purposes::CountedPurposes;
/// One group of trials: a tag, an action and a robot class (`None` for robots without one).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GroupKey<'a> {
    pub epc: &'a Epc,
    pub action: &'a str,
    pub robot_class: Option<&'a str>,
}

/// Groups as one JSON parameter, `[[epc, action, class or null], …]`: a batch of any size is one
/// statement with one text, so it is prepared once and costs one round trip.
pub fn groups_parameter(groups: &[GroupKey<'_>]) -> String {
    let rows: Vec<Value> =
        groups.iter().map(|g| json!([g.epc.as_hex(), g.action, g.robot_class])).collect();
    Value::Array(rows).to_string()
}

/// How each group went lately: the attempts and successes among its latest `window` trials of
/// the `counted` purposes, a person's verdict overriding the detector's, in the order of
/// `groups`. What *reliable* is judged on.
pub async fn latest_outcomes(
    conn: &mut AnyConnection,
    groups: &[GroupKey<'_>],
    window: i64,
    counted: &CountedPurposes,
) -> sqlx::Result<Vec<(i64, i64)>> {
    // Each group reads its newest trials down the (epc, action, class, seq) index; SQLite has
    // no lateral join, so it asks twice per group, which reads the same few index pages.
    sqlx::query_as(Dialect::of(conn).pick(
        "select
             (select count(*) from (
                  select 1 from trials
                  where epc = json_extract(g.value, '$[0]') and action = json_extract(g.value, '$[1]')
                    and coalesce(robot_class, '') = coalesce(json_extract(g.value, '$[2]'), '')
                    and purpose in (select value from json_each($3))
                  order by seq desc limit $2)),
             (select coalesce(sum(success), 0) from (
                  select case when confirmed = 1 or (confirmed is null and outcome = 'success')
                              then 1 else 0 end as success
                  from trials
                  where epc = json_extract(g.value, '$[0]') and action = json_extract(g.value, '$[1]')
                    and coalesce(robot_class, '') = coalesce(json_extract(g.value, '$[2]'), '')
                    and purpose in (select value from json_each($3))
                  order by seq desc limit $2))
         from json_each($1) as g order by g.key",
        "select count(latest.success), coalesce(sum(latest.success), 0)
         from jsonb_array_elements($1::jsonb) with ordinality as g(value, ord)
         left join lateral (
             select case when confirmed = 1 or (confirmed is null and outcome = 'success')
                         then 1 else 0 end as success
             from trials
             where epc = g.value->>0 and action = g.value->>1
               and coalesce(robot_class, '') = coalesce(g.value->>2, '')
               and purpose in (select jsonb_array_elements_text($3::jsonb))
             order by seq desc limit $2) as latest on true
         group by g.ord order by g.ord",
    ))
    .bind(groups_parameter(groups))
    .bind(window)
    .bind(counted.parameter())
    .fetch_all(conn)
    .await
}

/// One action as done by one robot class (`None` for robots without one), counted over all its
/// trials: (action, class, attempts, detected successes, verdicts, confirmed successes, verdicts
/// agreeing with the detector, successes by verdict else detector, last start).
pub type GroupCounts = (String, Option<String>, i64, i64, i64, i64, i64, i64, Option<String>);

/// Every action × robot class group of a tag's trials of the `counted` purposes, ordered by
/// action and class.
pub async fn group_counts(
    pool: &AnyPool,
    epc: &Epc,
    counted: &CountedPurposes,
) -> sqlx::Result<Vec<GroupCounts>> {
    let query = |purposes| {
        format!(
            "select action, robot_class, count(*),
                sum(case when outcome = 'success' then 1 else 0 end),
                sum(case when confirmed is not null then 1 else 0 end),
                sum(case when confirmed = 1 then 1 else 0 end),
                sum(case when confirmed = (case when outcome = 'success' then 1 else 0 end)
                         then 1 else 0 end),
                sum(case when confirmed = 1 or (confirmed is null and outcome = 'success')
                         then 1 else 0 end),
                max(started_at)
         from trials where epc = $1 and purpose in ({purposes})
         group by action, robot_class
         order by action, coalesce(robot_class, '')"
        )
    };
    let statement = query(
        Dialect::of_pool(pool)
            .pick("select value from json_each($2)", "select jsonb_array_elements_text($2::jsonb)"),
    );
    sqlx::query_as(sqlx::AssertSqlSafe(statement))
        .bind(epc.as_hex())
        .bind(counted.parameter())
        .fetch_all(pool)
        .await
}

/// How many of a tag's trials were made for each purpose: `(purpose, trials)`.
pub async fn purpose_counts(pool: &AnyPool, epc: &Epc) -> sqlx::Result<Vec<(String, i64)>> {
    sqlx::query_as(
        "select purpose, count(*) from trials where epc = $1 group by purpose order by purpose",
    )
    .bind(epc.as_hex())
    .fetch_all(pool)
    .await
}

/// The numbers at `path` (a JSON path into the trial body, e.g. `$.measurements.displacement`)
/// of a group's latest `window` successful trials of `behavior` in real use, newest first: an
/// experiment's trials teach nothing about how the thing behaves in use. A trial the person
/// said failed counts as none, whatever the detector thought; only numbers count, and JSON has
/// one number type, so 1 and 1.0 both are one.
pub async fn latest_measurements(
    conn: &mut AnyConnection,
    path: &str,
    epc: &Epc,
    robot_class: Option<&str>,
    behavior: &str,
    window: i64,
) -> sqlx::Result<Vec<f64>> {
    let dialect = Dialect::of(conn);
    let values: Vec<Option<f64>> = sqlx::query_scalar(dialect.pick(
        "select case when json_type(body, $1) in ('integer', 'real')
                     then cast(json_extract(body, $1) as real) end
         from trials
         where epc = $2 and coalesce(robot_class, '') = coalesce($3, '') and behavior = $4
           and purpose = 'use' and outcome = 'success' and coalesce(confirmed, 1) = 1
         order by seq desc limit $5",
        "select case when jsonb_typeof(jsonb_path_query_first(body::jsonb, $1::jsonpath)) = 'number'
                     then jsonb_path_query_first(body::jsonb, $1::jsonpath)::double precision end
         from trials
         where epc = $2 and coalesce(robot_class, '') = coalesce($3, '') and behavior = $4
           and purpose = 'use' and outcome = 'success' and coalesce(confirmed, 1) = 1
         order by seq desc limit $5",
    ))
    .bind(path)
    .bind(epc.as_hex())
    .bind(robot_class)
    .bind(behavior)
    .bind(window)
    .fetch_all(conn)
    .await?;
    Ok(values.into_iter().flatten().collect())
}
