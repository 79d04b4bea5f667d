//! EPCs robots read that nobody registered, so a caretaker can register them in one click.

use pps_schema::Epc;
use serde::Serialize;
use serde_json::{Value, json};
use sqlx::{AnyConnection, AnyPool};
use time::OffsetDateTime;

use crate::clock;
use crate::store::columns::{At, Flag};

use crate::store::events::{self, EventKind};

/// Sightings of one unknown EPC gathered in memory since the last flush.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sighting {
    pub epc: String,
    pub robots: Vec<String>,
    pub first_seen: OffsetDateTime,
    pub last_seen: OffsetDateTime,
    pub count: i64,
}

/// One inbox row as listed.
#[derive(Debug, Clone, Serialize)]
pub struct InboxItem {
    pub epc: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub epc_uri: Option<String>,
    pub robots: Vec<String>,
    #[serde(with = "clock::stored")]
    pub first_seen: OffsetDateTime,
    #[serde(with = "clock::stored")]
    pub last_seen: OffsetDateTime,
    pub count: i64,
}

/// EPCs the inbox keeps, at most: the most recently seen. A flood of made-up EPCs pushes out
/// the oldest sightings instead of growing the database.
pub const MAX_ENTRIES: i64 = 10_000;
/// EPCs one inbox event names, at most; a flush of more says how many more there were.
const EPCS_PER_EVENT: usize = 100;

/// Adds sightings to the inbox (skipping EPCs registered meanwhile), merged with earlier
/// sightings of the same EPC, then drops the oldest beyond [`MAX_ENTRIES`]. One event tells of
/// the whole flush, however many EPCs it held.
#[tracing::instrument(skip_all, fields(n = sightings.len()))]
pub async fn record(tx: &mut AnyConnection, sightings: &[Sighting]) -> sqlx::Result<usize> {
    let mut recorded = Vec::new();
    for sighting in sightings {
        let registered: Flag = sqlx::query_scalar(
            "select case when exists (select 1 from tags where epc = $1) then 1 else 0 end",
        )
        .bind(&sighting.epc)
        .fetch_one(&mut *tx)
        .await?;
        if registered.into() {
            continue;
        }
        let existing: Option<(String, At, i64)> =
            sqlx::query_as("select robots, first_seen, count from inbox where epc = $1")
                .bind(&sighting.epc)
                .fetch_optional(&mut *tx)
                .await?;
        let (robots, first_seen, count) = match existing {
            Some((robots, At(first_seen), count)) => {
                let mut known: Vec<String> = serde_json::from_str(&robots).unwrap_or_default();
                for robot in &sighting.robots {
                    if !known.contains(robot) {
                        known.push(robot.clone());
                    }
                }
                (known, first_seen, count + sighting.count)
            }
            None => (sighting.robots.clone(), sighting.first_seen, sighting.count),
        };
        sqlx::query(
            "insert into inbox (epc, robots, first_seen, last_seen, count) values ($1, $2, $3, $4, $5)
             on conflict (epc) do update set robots = excluded.robots,
                 last_seen = excluded.last_seen, count = excluded.count",
        )
        .bind(&sighting.epc)
        .bind(Value::from(robots).to_string())
        .bind(At(first_seen))
        .bind(At(sighting.last_seen))
        .bind(count)
        .execute(&mut *tx)
        .await?;
        recorded.push((sighting.epc.as_str(), count));
    }
    let data = match recorded.as_slice() {
        [] => return Ok(0),
        [(epc, count)] => json!({ "epc": epc, "count": count }),
        many => json!({
            "epcs": many.iter().take(EPCS_PER_EVENT).map(|(epc, _)| *epc).collect::<Vec<_>>(),
            "more": many.len().saturating_sub(EPCS_PER_EVENT),
        }),
    };
    events::append(tx, EventKind::InboxChanged, data).await?;
    sqlx::query(
        "delete from inbox where epc not in (
             select epc from inbox order by last_seen desc, epc limit $1)",
    )
    .bind(MAX_ENTRIES)
    .execute(&mut *tx)
    .await?;
    Ok(recorded.len())
}

/// Drops an EPC from the inbox once it is registered.
pub async fn forget(tx: &mut AnyConnection, epc: &Epc) -> sqlx::Result<()> {
    let removed = sqlx::query("delete from inbox where epc = $1")
        .bind(epc.as_hex())
        .execute(&mut *tx)
        .await?;
    if removed.rows_affected() > 0 {
        events::append(
            tx,
            EventKind::InboxChanged,
            json!({ "epc": epc.as_hex(), "registered": true }),
        )
        .await?;
    }
    Ok(())
}

/// Inbox rows after the EPC `after`, most recently seen first would reorder under writes, so
/// the list is in EPC order like every other cursor list.
pub async fn list(pool: &AnyPool, after: Option<&str>, limit: u32) -> sqlx::Result<Vec<InboxItem>> {
    let rows: Vec<(String, String, At, At, i64)> = sqlx::query_as(
        "select epc, robots, first_seen, last_seen, count from inbox
         where ($1 is null or epc > $1) order by epc limit $2",
    )
    .bind(after)
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await?;
    Ok(rows
        .into_iter()
        .map(|(epc, robots, At(first_seen), At(last_seen), count)| InboxItem {
            epc_uri: pps_schema::Epc::parse(&epc).ok().and_then(|e| e.pure_identity_uri()),
            robots: serde_json::from_str(&robots).unwrap_or_default(),
            epc,
            first_seen,
            last_seen,
            count,
        })
        .collect())
}
