//! Tag entries and their revision history in the database.
//!
//! Every write runs in one immediate transaction that checks the precondition against the
//! current revision, so of two caretakers saving the same revision exactly one wins.

use pps_schema::Epc;
use serde_json::{Value, json};
use sqlx::AnyPool;
use time::OffsetDateTime;

use super::WriteCondition;
use crate::clock;
use crate::store::columns::{At, Flag, Id, JsonText};
use crate::store::db::Db;
use crate::store::events::{self, EventKind};
use crate::store::{inbox, retired};

/// A tag as stored, with the metadata the registry keeps about it.
#[derive(Debug, Clone)]
pub struct StoredTag {
    pub epc: Epc,
    pub entry: Value,
    pub revision: i64,
    pub archived: bool,
    pub updated_at: OffsetDateTime,
    pub updated_by: String,
}

#[derive(sqlx::FromRow)]
struct TagRow {
    #[sqlx(try_from = "Id<Epc>")]
    epc: Epc,
    entry: String,
    revision: i64,
    #[sqlx(try_from = "Flag")]
    archived: bool,
    #[sqlx(try_from = "At")]
    updated_at: OffsetDateTime,
    updated_by: String,
}

impl TryFrom<TagRow> for StoredTag {
    type Error = sqlx::Error;
    fn try_from(row: TagRow) -> Result<Self, Self::Error> {
        Ok(Self {
            entry: serde_json::from_str(&row.entry).map_err(|e| sqlx::Error::Decode(e.into()))?,
            epc: row.epc,
            revision: row.revision,
            archived: row.archived,
            updated_at: row.updated_at,
            updated_by: row.updated_by,
        })
    }
}

/// Why a tag write did not happen.
#[derive(Debug, thiserror::Error)]
pub enum TagWriteError {
    #[error("a tag with this EPC already exists")]
    Exists { current: StoredTag },
    #[error("no tag has this EPC")]
    Missing,
    #[error("the tag changed since the revision the request names")]
    Stale { current: StoredTag },
    #[error("the EPC was retired when its tag was replaced; the tag now has the EPC {successor}")]
    Retired { successor: Epc },
    #[error(transparent)]
    Database(#[from] sqlx::Error),
}

/// Which tags a list wants.
#[derive(Debug, Default)]
pub struct TagFilter {
    pub kind: Option<String>,
    pub name_contains: Option<String>,
    pub archived: bool,
}

#[tracing::instrument(skip_all)]
pub async fn get(pool: &AnyPool, epc: &Epc) -> sqlx::Result<Option<StoredTag>> {
    current(&mut *pool.acquire().await?, epc).await
}

/// Up to `limit` tags after the EPC `after`, in EPC order.
#[tracing::instrument(skip_all)]
pub async fn list(
    pool: &AnyPool,
    filter: &TagFilter,
    after: Option<&str>,
    limit: u32,
) -> sqlx::Result<Vec<StoredTag>> {
    let pattern = filter.name_contains.as_deref().map(like_pattern);
    let rows: Vec<TagRow> = sqlx::query_as(
        "select epc, entry, revision, archived, updated_at, updated_by from tags
         where archived = $1
           and (cast($2 as text) is null or kind = $2)
           and (cast($3 as text) is null or lower(name) like $3 escape '\\')
           and (cast($4 as text) is null or epc > $4)
         order by epc
         limit $5",
    )
    .bind(i64::from(filter.archived))
    .bind(&filter.kind)
    .bind(&pattern)
    .bind(after)
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await?;
    rows.into_iter().map(StoredTag::try_from).collect()
}

/// A case-insensitive substring pattern for LIKE over `lower(name)`, with the user's `%` and
/// `_` taken literally. Lower-cased here and in the statement, since SQLite's LIKE ignores
/// ASCII case and PostgreSQL's does not.
fn like_pattern(text: &str) -> String {
    let text = text.to_ascii_lowercase();
    let escaped = text.replace('\\', "\\\\").replace('%', "\\%").replace('_', "\\_");
    format!("%{escaped}%")
}

/// Creates or replaces the tag under `condition`, recording the revision.
#[tracing::instrument(skip_all, fields(epc = %epc))]
pub async fn put(
    db: &Db,
    epc: &Epc,
    entry: &Value,
    condition: &WriteCondition,
    by: &str,
) -> Result<(StoredTag, bool), TagWriteError> {
    let mut tx = db.begin_write().await?;
    let written = put_in(&mut tx, epc, entry, condition, by).await?;
    tx.commit().await?;
    Ok(written)
}

/// [`put`] inside the caller's transaction; true when the tag was created.
pub async fn put_in(
    tx: &mut sqlx::AnyConnection,
    epc: &Epc,
    entry: &Value,
    condition: &WriteCondition,
    by: &str,
) -> Result<(StoredTag, bool), TagWriteError> {
    let current = current(tx, epc).await?;
    let (revision, change) = match (&current, condition) {
        (Some(current), WriteCondition::Absent) => {
            return Err(TagWriteError::Exists { current: current.clone() });
        }
        (None, WriteCondition::Absent) => {
            // A retired EPC stays retired: robots reading it are sent on to its successor.
            if let Some(successor) = retired::successor(tx, epc).await? {
                return Err(TagWriteError::Retired { successor });
            }
            (1, "create")
        }
        (None, _) => return Err(TagWriteError::Missing),
        (Some(current), condition) if !condition.allows(current.revision) => {
            return Err(TagWriteError::Stale { current: current.clone() });
        }
        (Some(current), _) => {
            (current.revision + 1, if current.archived { "restore" } else { "replace" })
        }
    };
    let stored = StoredTag {
        epc: epc.clone(),
        entry: entry.clone(),
        revision,
        archived: false,
        updated_at: clock::recorded_now(),
        updated_by: by.to_owned(),
    };
    write(tx, &stored, change).await?;
    Ok((stored, change == "create"))
}

/// Archives the tag under `condition`; its trials are kept.
#[tracing::instrument(skip_all, fields(epc = %epc))]
pub async fn archive(
    db: &Db,
    epc: &Epc,
    condition: &WriteCondition,
    by: &str,
) -> Result<StoredTag, TagWriteError> {
    let mut tx = db.begin_write().await?;
    let archived = archive_in(&mut tx, epc, condition, by).await?;
    tx.commit().await?;
    Ok(archived)
}

/// [`archive`] inside the caller's transaction.
pub async fn archive_in(
    tx: &mut sqlx::AnyConnection,
    epc: &Epc,
    condition: &WriteCondition,
    by: &str,
) -> Result<StoredTag, TagWriteError> {
    let Some(current) = current(tx, epc).await? else {
        return Err(TagWriteError::Missing);
    };
    if !condition.allows(current.revision) {
        return Err(TagWriteError::Stale { current });
    }
    if current.archived {
        return Ok(current);
    }
    let stored = StoredTag {
        revision: current.revision + 1,
        archived: true,
        updated_at: clock::recorded_now(),
        updated_by: by.to_owned(),
        ..current
    };
    write(tx, &stored, "archive").await?;
    // No robot may record a trial on an archived tag, so nothing asked of it can be done.
    let reason = format!("the tag was archived by {by}");
    crate::store::tasks::cancel_on_tag(tx, &stored.epc, &reason, clock::recorded_now()).await?;
    Ok(stored)
}

/// The stored entry of the tag with this EPC, `None` when there is none or it does not parse;
/// for the trial writer's learning, inside its transaction.
pub async fn entry_of(
    conn: &mut sqlx::AnyConnection,
    epc: &Epc,
) -> sqlx::Result<Option<serde_json::Value>> {
    let entry: Option<String> = sqlx::query_scalar("select entry from tags where epc = $1")
        .bind(epc.as_hex())
        .fetch_optional(conn)
        .await?;
    Ok(entry.and_then(|e| serde_json::from_str(&e).ok()))
}

/// Whether the tag with this EPC is archived; `None` when no tag has it.
pub async fn is_archived(conn: &mut sqlx::AnyConnection, epc: &Epc) -> sqlx::Result<Option<bool>> {
    let archived: Option<Flag> = sqlx::query_scalar("select archived from tags where epc = $1")
        .bind(epc.as_hex())
        .fetch_optional(conn)
        .await?;
    Ok(archived.map(bool::from))
}

pub async fn current(tx: &mut sqlx::AnyConnection, epc: &Epc) -> sqlx::Result<Option<StoredTag>> {
    let row: Option<TagRow> = sqlx::query_as(
        "select epc, entry, revision, archived, updated_at, updated_by from tags where epc = $1",
    )
    .bind(epc.as_hex())
    .fetch_optional(&mut *tx)
    .await?;
    row.map(StoredTag::try_from).transpose()
}

async fn write(tx: &mut sqlx::AnyConnection, tag: &StoredTag, change: &str) -> sqlx::Result<()> {
    let entry = tag.entry.to_string();
    let properties = tag.entry.get("properties");
    let text = |key: &str| {
        properties.and_then(|p| p.get(key)).and_then(Value::as_str).unwrap_or("").to_owned()
    };
    sqlx::query(
        "insert into tags (epc, entry, kind, name, revision, archived, updated_at, updated_by)
         values ($1, $2, $3, $4, $5, $6, $7, $8)
         on conflict (epc) do update set entry = excluded.entry, kind = excluded.kind,
             name = excluded.name, revision = excluded.revision, archived = excluded.archived,
             updated_at = excluded.updated_at, updated_by = excluded.updated_by",
    )
    .bind(tag.epc.as_hex())
    .bind(&entry)
    .bind(text("type"))
    .bind(text("name"))
    .bind(tag.revision)
    .bind(i64::from(tag.archived))
    .bind(At(tag.updated_at))
    .bind(&tag.updated_by)
    .execute(&mut *tx)
    .await?;
    sqlx::query(
        "insert into tag_revisions (epc, revision, change, entry, archived, changed_at, changed_by)
         values ($1, $2, $3, $4, $5, $6, $7)",
    )
    .bind(tag.epc.as_hex())
    .bind(tag.revision)
    .bind(change)
    .bind(&entry)
    .bind(i64::from(tag.archived))
    .bind(At(tag.updated_at))
    .bind(&tag.updated_by)
    .execute(&mut *tx)
    .await?;
    let kind = if change == "archive" { EventKind::TagArchived } else { EventKind::TagChanged };
    events::append(tx, kind, json!({ "epc": tag.epc, "revision": tag.revision, "change": change }))
        .await?;
    if change == "create" {
        inbox::forget(tx, &tag.epc).await?;
    }
    Ok(())
}

/// One change in a tag's history.
#[derive(Debug, serde::Serialize, sqlx::FromRow)]
pub struct Revision {
    pub revision: i64,
    pub change: String,
    #[sqlx(try_from = "Flag")]
    pub archived: bool,
    #[serde(with = "clock::stored")]
    #[sqlx(try_from = "At")]
    pub changed_at: OffsetDateTime,
    pub changed_by: String,
    #[sqlx(try_from = "JsonText")]
    pub entry: Value,
}

/// Revisions of a tag, oldest first, after revision `after`.
#[tracing::instrument(skip_all)]
pub async fn revisions(
    pool: &AnyPool,
    epc: &Epc,
    after: i64,
    limit: u32,
) -> sqlx::Result<Vec<Revision>> {
    sqlx::query_as(
        "select revision, change, archived, changed_at, changed_by, entry from tag_revisions
         where epc = $1 and revision > $2 order by revision limit $3",
    )
    .bind(epc.as_hex())
    .bind(after)
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await
}

/// How many tags the registry holds, archived ones included.
pub async fn count(executor: impl sqlx::AnyExecutor<'_>) -> sqlx::Result<i64> {
    sqlx::query_scalar("select count(*) from tags").fetch_one(executor).await
}

/// Every tag, archived ones included, in EPC order (for export).
pub async fn all(pool: &AnyPool) -> sqlx::Result<Vec<StoredTag>> {
    let rows: Vec<TagRow> = sqlx::query_as(
        "select epc, entry, revision, archived, updated_at, updated_by from tags order by epc",
    )
    .fetch_all(pool)
    .await?;
    rows.into_iter().map(StoredTag::try_from).collect()
}

/// Moves a tag and its whole history to a new EPC (a worn tag replaced), as a new revision.
pub async fn move_to(
    tx: &mut sqlx::AnyConnection,
    current: &StoredTag,
    new: &Epc,
    by: &str,
) -> sqlx::Result<StoredTag> {
    sqlx::query("update tag_revisions set epc = $1 where epc = $2")
        .bind(new.as_hex())
        .bind(current.epc.as_hex())
        .execute(&mut *tx)
        .await?;
    sqlx::query("delete from tags where epc = $1")
        .bind(current.epc.as_hex())
        .execute(&mut *tx)
        .await?;
    let mut entry = current.entry.clone();
    if let Some(object) = entry.as_object_mut() {
        object.insert("epc".into(), new.as_hex().into());
    }
    let moved = StoredTag {
        epc: new.clone(),
        entry,
        revision: current.revision + 1,
        archived: current.archived,
        updated_at: clock::recorded_now(),
        updated_by: by.to_owned(),
    };
    write(tx, &moved, "retag").await?;
    inbox::forget(tx, new).await?;
    Ok(moved)
}
