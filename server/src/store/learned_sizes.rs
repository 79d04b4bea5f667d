//! Learned tag sizes (`learned_sizes`), one per tag, and the measurements of trials they are
//! learned from. What a learned size is, and how it is learned, is `learning::size`'s.

use pps_schema::{Epc, TagSize};
use sqlx::{AnyConnection, AnyPool};

use crate::clock;
use crate::store::columns::At;
use crate::store::db::Dialect;

/// A tag's size learned from its confirmed reads, and how many it rests on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LearnedSize {
    pub size: TagSize,
    pub trials: u64,
}

/// The learned size of `epc`, as stored.
pub async fn learned(pool: &AnyPool, epc: &Epc) -> sqlx::Result<Option<LearnedSize>> {
    let row: Option<(f64, f64, i64)> =
        sqlx::query_as("select width, height, trials from learned_sizes where epc = $1")
            .bind(epc.as_hex())
            .fetch_optional(pool)
            .await?;
    Ok(row.map(|(width, height, trials)| LearnedSize {
        size: TagSize { width, height },
        trials: trials as u64,
    }))
}

/// The sizes measured in the latest `window` real-use trials of `epc` that a person confirmed.
pub async fn measurements(
    conn: &mut AnyConnection,
    epc: &Epc,
    window: i64,
) -> sqlx::Result<Vec<TagSize>> {
    let dialect = Dialect::of(conn);
    let rows: Vec<Option<String>> = sqlx::query_scalar(dialect.pick(
        "select json_extract(body, '$.tag_size') from trials
         where epc = $1 and purpose = 'use' and confirmed = 1
           and json_type(body, '$.tag_size') = 'object'
         order by seq desc limit $2",
        "select (body::jsonb -> 'tag_size')::text from trials
         where epc = $1 and purpose = 'use' and confirmed = 1
           and jsonb_typeof(body::jsonb -> 'tag_size') = 'object'
         order by seq desc limit $2",
    ))
    .bind(epc.as_hex())
    .bind(window)
    .fetch_all(conn)
    .await?;
    Ok(rows.into_iter().flatten().filter_map(|text| serde_json::from_str(&text).ok()).collect())
}

/// Stores (or, with `None`, forgets) the learned size of `epc`; true when it changed.
pub async fn store(
    conn: &mut AnyConnection,
    epc: &Epc,
    learned: Option<LearnedSize>,
) -> sqlx::Result<bool> {
    let previous: Option<(f64, f64, i64)> =
        sqlx::query_as("select width, height, trials from learned_sizes where epc = $1")
            .bind(epc.as_hex())
            .fetch_optional(&mut *conn)
            .await?;
    let Some(LearnedSize { size, trials }) = learned else {
        if previous.is_some() {
            sqlx::query("delete from learned_sizes where epc = $1")
                .bind(epc.as_hex())
                .execute(conn)
                .await?;
        }
        return Ok(previous.is_some());
    };
    if previous == Some((size.width, size.height, trials as i64)) {
        return Ok(false);
    }
    sqlx::query(
        "insert into learned_sizes (epc, width, height, trials, updated_at)
         values ($1, $2, $3, $4, $5)
         on conflict (epc) do update set width = excluded.width, height = excluded.height,
             trials = excluded.trials, updated_at = excluded.updated_at",
    )
    .bind(epc.as_hex())
    .bind(size.width)
    .bind(size.height)
    .bind(trials as i64)
    .bind(At(clock::recorded_now()))
    .execute(conn)
    .await?;
    Ok(true)
}
