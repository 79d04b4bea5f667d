//! Opening the registry's SQLite database: WAL, full fsync, foreign keys, migrations.
//!
//! Reads go through a pool; writes through a single connection, so in-process writers queue
//! on the pool instead of spinning on SQLite's busy handler.

use std::path::Path;
use std::str::FromStr;
use std::time::Duration;

use anyhow::Context;
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Sqlite, SqlitePool, Transaction};

static MIGRATIONS: sqlx::migrate::Migrator = sqlx::migrate!("../migrations");

/// The database handle shared by every request.
#[derive(Debug, Clone)]
pub struct Db {
    read: SqlitePool,
    write: SqlitePool,
}

impl Db {
    /// Opens (creating if missing) and migrates the database at `path`.
    pub async fn open(path: &Path) -> anyhow::Result<Self> {
        let options = SqliteConnectOptions::from_str("sqlite:")?
            .filename(path)
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            // An acknowledged write must survive power loss: fsync the WAL on every commit.
            .synchronous(SqliteSynchronous::Full)
            .foreign_keys(true)
            // Another process (the CLI, a backup) may hold the write lock for a moment.
            .busy_timeout(Duration::from_secs(10));
        let write = SqlitePoolOptions::new()
            .max_connections(1)
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
        Ok(Self { read, write })
    }

    /// The pool for queries that only read.
    pub fn reader(&self) -> &SqlitePool {
        &self.read
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
