//! `pps-server backup`: a consistent copy of the live database, taken while the server serves.
//!
//! `VACUUM INTO` reads one snapshot of the database in a read transaction, so the copy holds
//! exactly the writes committed before it began, however many robots write meanwhile, and it
//! never blocks them. The copy is written beside the target under a temporary name, checked,
//! and only then renamed into place: a backup that stops half-way never looks like a backup.
//! This module must never write to the source database.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use anyhow::{Context, bail};
use sqlx::sqlite::SqliteConnectOptions;
use sqlx::{Connection, SqliteConnection};

use crate::db::Db;

/// What a backup holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BackupReport {
    pub path: PathBuf,
    pub bytes: u64,
    /// Tags, archived ones included.
    pub tags: i64,
    pub trials: i64,
    /// Trial pictures whose bytes the copy holds.
    pub pictures: i64,
}

/// What `backup` says on a PostgreSQL registry, whose own tools take consistent copies.
pub const NOT_ON_POSTGRES: &str = "backup copies a SQLite registry file; a PostgreSQL registry \
    is backed up with PostgreSQL's own pg_dump (for example pg_dump --format=custom --file \
    pps.dump DB), which takes one consistent snapshot while the replicas serve";

/// Copies the SQLite file `db` was opened from to `to`; an existing `to` is replaced only when
/// `replace` is set, and never when it is the database itself.
pub async fn backup(db: &Db, to: &Path, replace: bool) -> anyhow::Result<BackupReport> {
    let Some(source) = db.location().file() else {
        bail!("{NOT_ON_POSTGRES}");
    };
    if same_file(source, to) {
        bail!("{} is the database itself; back it up to another file", to.display());
    }
    if to.exists() && !replace {
        bail!("{} already exists; choose a new file or pass --force to replace it", to.display());
    }
    if let Some(dir) = to.parent().filter(|dir| !dir.as_os_str().is_empty() && !dir.is_dir()) {
        bail!(
            "cannot write the backup {}: the directory {} does not exist",
            to.display(),
            dir.display()
        );
    }
    let partial = partial_path(to)?;
    let _ = std::fs::remove_file(&partial);
    // SQLite writes into an empty file it is given, keeping its owner-only mode.
    crate::private_file::options()
        .create_new(true)
        .open(&partial)
        .with_context(|| format!("cannot create the backup {}", partial.display()))?;
    let copied = async {
        let mut conn = db.reader().acquire().await?;
        sqlx::query("vacuum into $1")
            .bind(partial.to_string_lossy().as_ref())
            .execute(&mut *conn)
            .await
            .with_context(|| format!("cannot write the backup {}", partial.display()))?;
        drop(conn);
        let report = inspect(&partial).await?;
        // On disk before it takes the final name, so a crash never leaves a torn "backup".
        std::fs::File::open(&partial)?.sync_all()?;
        std::fs::rename(&partial, to)
            .with_context(|| format!("cannot move the backup into place at {}", to.display()))?;
        Ok(BackupReport { path: to.to_owned(), ..report })
    }
    .await;
    if copied.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    copied
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// The temporary name the copy is written under, in the target's directory so the final
/// rename cannot cross file systems.
fn partial_path(to: &Path) -> anyhow::Result<PathBuf> {
    let name = to
        .file_name()
        .with_context(|| format!("{} is not a file name to write a backup to", to.display()))?;
    let mut partial = name.to_os_string();
    partial.push(".partial");
    Ok(to.with_file_name(partial))
}

/// Checks a copy's integrity and counts what it holds.
async fn inspect(path: &Path) -> anyhow::Result<BackupReport> {
    let options = SqliteConnectOptions::from_str("sqlite:")?.filename(path);
    let mut conn = SqliteConnection::connect_with(&options)
        .await
        .with_context(|| format!("cannot open the backup {}", path.display()))?;
    let integrity: String =
        sqlx::query_scalar("pragma integrity_check").fetch_one(&mut conn).await?;
    if integrity != "ok" {
        bail!("the backup {} failed its integrity check: {integrity}", path.display());
    }
    let tags = sqlx::query_scalar("select count(*) from tags").fetch_one(&mut conn).await?;
    let trials = sqlx::query_scalar("select count(*) from trials").fetch_one(&mut conn).await?;
    let pictures =
        sqlx::query_scalar("select count(*) from trial_pictures where bytes is not null")
            .fetch_one(&mut conn)
            .await?;
    conn.close().await?;
    let bytes = std::fs::metadata(path)?.len();
    Ok(BackupReport { path: path.to_owned(), bytes, tags, trials, pictures })
}
