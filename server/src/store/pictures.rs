//! Trial pictures in the database: at most one per trial, its bytes kept until the tag's
//! retention rule removes them (the row and its digest stay, so a resend is still a retry).

use sqlx::{AnyConnection, AnyPool};
use time::OffsetDateTime;
use uuid::Uuid;

use crate::store::columns::{At, MaybeAt};
use crate::store::db::Dialect;
use crate::trials::picture::Picture;

/// A stored picture's description, without its bytes.
#[derive(Debug, Clone, PartialEq, Eq, sqlx::FromRow)]
pub struct PictureRow {
    pub media_type: String,
    pub sha256: String,
    #[sqlx(try_from = "MaybeAt")]
    pub removed_at: Option<OffsetDateTime>,
}

/// A stored picture with its bytes; `bytes` is `None` once retention removed them.
#[derive(Debug, Clone, PartialEq, Eq, sqlx::FromRow)]
pub struct StoredPicture {
    pub media_type: String,
    pub sha256: String,
    pub bytes: Option<Vec<u8>>,
}

/// Stores a trial's picture unless it has one already (also one retention removed); true when
/// this call stored it.
pub async fn insert_new(
    conn: &mut AnyConnection,
    trial: &Uuid,
    picture: &Picture,
    bytes: &[u8],
    received_at: OffsetDateTime,
) -> sqlx::Result<bool> {
    let done = sqlx::query(
        "insert into trial_pictures
             (trial, media_type, bytes, sha256, size, width, height, received_at)
         values ($1, $2, $3, $4, $5, $6, $7, $8)
         on conflict (trial) do nothing",
    )
    .bind(trial.hyphenated().to_string())
    .bind(picture.kind.media_type())
    .bind(bytes.to_vec())
    .bind(&picture.sha256)
    .bind(bytes.len() as i64)
    .bind(i64::from(picture.width))
    .bind(i64::from(picture.height))
    .bind(At(received_at))
    .execute(conn)
    .await?;
    Ok(done.rows_affected() == 1)
}

/// The picture a trial has, described.
pub async fn describe(conn: &mut AnyConnection, trial: &Uuid) -> sqlx::Result<Option<PictureRow>> {
    sqlx::query_as("select media_type, sha256, removed_at from trial_pictures where trial = $1")
        .bind(trial.hyphenated().to_string())
        .fetch_optional(conn)
        .await
}

/// The picture a trial has, with its bytes.
#[tracing::instrument(skip_all)]
pub async fn get(pool: &AnyPool, trial: &Uuid) -> sqlx::Result<Option<StoredPicture>> {
    sqlx::query_as("select media_type, sha256, bytes from trial_pictures where trial = $1")
        .bind(trial.hyphenated().to_string())
        .fetch_optional(pool)
        .await
}

/// The newest picture still held of the tag `epc`'s trials (newest by the trial's place in
/// arrival order), with its bytes.
#[tracing::instrument(skip_all)]
pub async fn newest_of_tag(pool: &AnyPool, epc: &str) -> sqlx::Result<Option<StoredPicture>> {
    sqlx::query_as(
        "select p.media_type, p.sha256, p.bytes
           from trial_pictures p join trials t on t.id = p.trial
          where t.epc = $1 and p.bytes is not null
          order by t.seq desc
          limit 1",
    )
    .bind(epc)
    .fetch_optional(pool)
    .await
}

/// Removes the bytes of every picture of the tag `epc` but the newest `keep` (newest by the
/// trial's place in arrival order); returns how many it removed.
pub async fn keep_newest(
    conn: &mut AnyConnection,
    epc: &str,
    keep: u32,
    now: OffsetDateTime,
) -> sqlx::Result<u64> {
    let done = sqlx::query(Dialect::of(conn).pick(
        "update trial_pictures set bytes = null, removed_at = $3
         where trial in (
             select p.trial from trial_pictures p join trials t on t.id = p.trial
             where t.epc = $1 and p.bytes is not null
             order by t.seq desc limit -1 offset $2)",
        "update trial_pictures set bytes = null, removed_at = $3
         where trial in (
             select p.trial from trial_pictures p join trials t on t.id = p.trial
             where t.epc = $1 and p.bytes is not null
             order by t.seq desc limit all offset $2)",
    ))
    .bind(epc)
    .bind(i64::from(keep))
    .bind(At(now))
    .execute(conn)
    .await?;
    Ok(done.rows_affected())
}

/// Tags holding more than `keep` pictures.
#[tracing::instrument(skip_all)]
pub async fn tags_over(pool: &AnyPool, keep: u32) -> sqlx::Result<Vec<String>> {
    sqlx::query_scalar(
        "select t.epc from trial_pictures p join trials t on t.id = p.trial
         where p.bytes is not null group by t.epc having count(*) > $1 order by t.epc",
    )
    .bind(i64::from(keep))
    .fetch_all(pool)
    .await
}
