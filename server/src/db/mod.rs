//! Opening the registry's SQLite database: WAL, full fsync, foreign keys, migrations.
//!
//! Reads go through a pool; writes through a single connection, so in-process writers queue
//! on the pool instead of spinning on SQLite's busy handler. A write connection left inside a
//! transaction (a commit or rollback that failed, as on a full disk) is closed rather than
//! reused, so the next write starts on a fresh one.

mod readiness;
mod unwritable;

use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Arc;
use std::time::Duration;

use anyhow::Context;
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Connection, Sqlite, SqliteConnection, SqlitePool, Transaction};

pub use readiness::NotReady;
pub use unwritable::Unwritable;

static MIGRATIONS: sqlx::migrate::Migrator = sqlx::migrate!("../migrations");

/// How long a write waits for a lock another process holds before it is answered 503.
const BUSY_TIMEOUT: Duration = Duration::from_secs(10);

/// The database handle shared by every request.
#[derive(Debug, Clone)]
pub struct Db {
    read: SqlitePool,
    write: SqlitePool,
    path: Arc<PathBuf>,
    /// Held by the one readiness probe that may wait for the write lock at a time.
    probe: Arc<tokio::sync::Mutex<()>>,
}

impl Db {
    /// Opens (creating if missing) and migrates the database at `path`.
    pub async fn open(path: &Path) -> anyhow::Result<Self> {
        create_private(path)?;
        let options = SqliteConnectOptions::from_str("sqlite:")?
            .filename(path)
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            // An acknowledged write must survive power loss: fsync the WAL on every commit.
            .synchronous(SqliteSynchronous::Full)
            .foreign_keys(true)
            // Another process (the CLI, a backup) may hold the write lock for a moment.
            .busy_timeout(BUSY_TIMEOUT);
        let write = SqlitePoolOptions::new()
            .max_connections(1)
            .after_release(|conn, _| Box::pin(outside_transaction(conn)))
            // A write dropped half-way (its client went away) may have left a BEGIN running.
            .before_acquire(|conn, _| Box::pin(outside_transaction(conn)))
            .connect_with(options.clone())
            .await
            .with_context(|| format!("cannot open the database {}", path.display()))?;
        MIGRATIONS
            .run(&write)
            .await
            .with_context(|| format!("cannot migrate the database {}", path.display()))?;
        let read = SqlitePoolOptions::new()
            .max_connections(8)
            .connect_with(options.read_only(true))
            .await
            .with_context(|| format!("cannot open the database {} for reading", path.display()))?;
        Ok(Self { read, write, path: Arc::new(path.to_owned()), probe: Arc::default() })
    }

    /// The pool for queries that only read.
    pub fn reader(&self) -> &SqlitePool {
        &self.read
    }

    /// The database file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Starts a write transaction holding SQLite's write lock from its first statement, so a
    /// read-then-write transaction cannot fail to upgrade when another process wrote meanwhile.
    pub async fn begin_write(&self) -> sqlx::Result<Transaction<'static, Sqlite>> {
        self.write.begin_with("begin immediate").await
    }

    /// Closes both pools, checkpointing the WAL.
    pub async fn close(&self) {
        self.read.close().await;
        self.write.close().await;
    }
}

/// Whether a write connection may be used again: not when it is stuck inside a transaction
/// (a commit and its rollback both failed, as on a full disk), which would make every later
/// `begin` fail. The pool then closes it and opens a fresh one.
async fn outside_transaction(conn: &mut SqliteConnection) -> sqlx::Result<bool> {
    if !conn.is_in_transaction() {
        return Ok(true);
    }
    // A dropped transaction's rollback is queued on the connection; once it has run the
    // depth is back to zero, unless the rollback failed too.
    conn.ping().await?;
    let stuck = conn.is_in_transaction();
    if stuck {
        tracing::warn!("a write connection was left inside a transaction; reopening it");
    }
    Ok(!stuck)
}

/// Creates a missing database file readable by its owner alone: it holds password and token
/// hashes. SQLite gives its `-wal` and `-shm` files the same permissions.
fn create_private(path: &Path) -> anyhow::Result<()> {
    match crate::private_file::options().create_new(true).open(path) {
        Ok(_) => Ok(()),
        Err(error) if error.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(error) => {
            Err(error).with_context(|| format!("cannot create the database {}", path.display()))
        }
    }
}
