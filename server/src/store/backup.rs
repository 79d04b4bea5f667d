//! The SQL of `pps-server backup` (the files around it are `ops::backup`'s): one snapshot of
//! the live SQLite database written into a new file, and what a copy holds.

use std::path::Path;
use std::str::FromStr;

use anyhow::Context;
use sqlx::sqlite::SqliteConnectOptions;
use sqlx::{Connection, SqliteConnection};

use super::db::Db;

/// What a copy holds, counted in the copy itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Contents {
    /// Tags, archived ones included.
    pub tags: i64,
    pub trials: i64,
    /// Trial pictures whose bytes the copy holds.
    pub pictures: i64,
}

/// Writes one consistent snapshot of `db` into the empty file `to`. `VACUUM INTO` reads it in a
/// read transaction: it holds exactly the writes committed before it began and never blocks
/// a writer.
pub async fn vacuum_into(db: &Db, to: &Path) -> anyhow::Result<()> {
    let mut conn = db.reader().acquire().await?;
    sqlx::query("vacuum into $1")
        .bind(to.to_string_lossy().as_ref())
        .execute(&mut *conn)
        .await
        .with_context(|| format!("cannot write the backup {}", to.display()))?;
    Ok(())
}

/// Checks the integrity of the SQLite file at `path` and counts what it holds; an `Err` names
/// what the integrity check found instead.
pub async fn inspect(path: &Path) -> anyhow::Result<Result<Contents, String>> {
    let options = SqliteConnectOptions::from_str("sqlite:")?.filename(path);
    let mut conn = SqliteConnection::connect_with(&options)
        .await
        .with_context(|| format!("cannot open the backup {}", path.display()))?;
    let integrity: String =
        sqlx::query_scalar("pragma integrity_check").fetch_one(&mut conn).await?;
    if integrity != "ok" {
        return Ok(Err(integrity));
    }
    let tags = sqlx::query_scalar("select count(*) from tags").fetch_one(&mut conn).await?;
    let trials = sqlx::query_scalar("select count(*) from trials").fetch_one(&mut conn).await?;
    let pictures =
        sqlx::query_scalar("select count(*) from trial_pictures where bytes is not null")
            .fetch_one(&mut conn)
            .await?;
    conn.close().await?;
    Ok(Ok(Contents { tags, trials, pictures }))
}
