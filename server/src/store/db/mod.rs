//! Opening the registry's database, SQLite or PostgreSQL, and the one way to write to it.
//!
//! Both engines are reached through sqlx's `Any` driver, so the store's SQL is written once;
//! [`Dialect`] names the few places where the two spell a thing differently.
//!
//! Reads go through a pool; writes through a single connection per process, so in-process
//! writers queue on the pool instead of spinning on a lock. On SQLite a write transaction takes
//! the file's write lock at its first statement (`begin immediate`); on PostgreSQL it takes one
//! transaction-scoped advisory lock, so writes from every replica are serialised the same way.
//! The store's read-then-write steps (revisions, idempotent trials, claims, seeding) and the
//! change feed's gap-free event order rest on that. A write connection left inside a
//! transaction (a commit or rollback that failed, as on a full disk) is closed rather than
//! reused, so the next write starts on a fresh one.

mod dialect;
mod location;
mod missing;
mod readiness;
mod unwritable;

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use anyhow::{Context, bail};
use sqlx::AnyConnection;
use sqlx::any::AnyPoolOptions;
use sqlx::{Any, AnyPool, Connection, Transaction};

pub use dialect::Dialect;
pub use location::Location;
pub use readiness::NotReady;
pub use unwritable::Unwritable;

static SQLITE_MIGRATIONS: sqlx::migrate::Migrator = sqlx::migrate!("../migrations");
static POSTGRES_MIGRATIONS: sqlx::migrate::Migrator = sqlx::migrate!("../migrations/postgres");

/// How long a write waits for a lock another process holds before it is answered 503, unless
/// the operator says otherwise (`serve --lock-timeout`).
pub const DEFAULT_LOCK_TIMEOUT: Duration = Duration::from_secs(10);
/// Connections for reads, per process.
const READERS: u32 = 8;
/// The advisory lock every PostgreSQL write transaction holds: the registry's write lock.
const POSTGRES_WRITE_LOCK: i64 = 0x5050_5354_4147; // "PPSTAG"

/// The database handle shared by every request.
#[derive(Debug, Clone)]
pub struct Db {
    read: AnyPool,
    write: AnyPool,
    dialect: Dialect,
    location: Arc<Location>,
    /// Held by the one readiness probe that may wait for the write lock at a time.
    probe: Arc<tokio::sync::Mutex<()>>,
    /// How long a write waits for the lock before giving up.
    lock_timeout: Duration,
}

impl Db {
    /// Opens (creating a missing SQLite file) and migrates the database at `location`.
    pub async fn open(location: &Location) -> anyhow::Result<Self> {
        Self::open_as(location, Create::IfMissing, DEFAULT_LOCK_TIMEOUT).await
    }

    /// Like [`Db::open`], with writes waiting at most `lock_timeout` for a lock another process
    /// holds (on PostgreSQL: for a connection) before they fail, to be answered 503.
    pub async fn open_waiting(location: &Location, lock_timeout: Duration) -> anyhow::Result<Self> {
        Self::open_as(location, Create::IfMissing, lock_timeout).await
    }

    /// Opens and migrates the registry at `location`, refusing one that does not exist yet:
    /// for every command but `serve` and `migrate`, a missing database is a typo or the wrong
    /// directory, and a fresh empty one would only hide that.
    pub async fn open_existing(location: &Location) -> anyhow::Result<Self> {
        Self::open_as(location, Create::Never, DEFAULT_LOCK_TIMEOUT).await
    }

    async fn open_as(
        location: &Location,
        create: Create,
        lock_timeout: Duration,
    ) -> anyhow::Result<Self> {
        sqlx::any::install_default_drivers();
        if let (Location::File(path), Create::Never) = (location, create)
            && !path.exists()
        {
            bail!("{}", missing::sqlite(path));
        }
        let (read, write, dialect) = match location {
            Location::File(path) => open_sqlite(path, lock_timeout).await?,
            Location::Postgres(url) => open_postgres(url, location, lock_timeout).await?,
        };
        if create == Create::Never && dialect == Dialect::Postgres && !migrated(&write).await? {
            read.close().await;
            write.close().await;
            bail!("{}", missing::postgres(location));
        }
        let migrations = match dialect {
            Dialect::Sqlite => &SQLITE_MIGRATIONS,
            Dialect::Postgres => &POSTGRES_MIGRATIONS,
        };
        // On PostgreSQL the migrator holds an advisory lock of its own, so replicas starting
        // together migrate once.
        migrations
            .run(&write)
            .await
            .with_context(|| format!("cannot migrate the database {location}"))?;
        Ok(Self {
            read,
            write,
            dialect,
            location: Arc::new(location.clone()),
            probe: Arc::default(),
            lock_timeout,
        })
    }

    /// Opens the SQLite file at `path`; a shorthand for tests and tools.
    pub async fn open_file(path: &Path) -> anyhow::Result<Self> {
        Self::open(&Location::File(path.to_owned())).await
    }

    /// The pool for queries that only read.
    pub fn reader(&self) -> &AnyPool {
        &self.read
    }

    /// Which engine this is, for the few statements the two spell differently.
    pub fn dialect(&self) -> Dialect {
        self.dialect
    }

    /// Where the database is.
    pub fn location(&self) -> &Location {
        &self.location
    }

    /// Starts a write transaction holding the registry's write lock from its first statement,
    /// so a read-then-write transaction sees every write committed before it and none during.
    pub async fn begin_write(&self) -> sqlx::Result<Transaction<'static, Any>> {
        match self.dialect {
            Dialect::Sqlite => self.write.begin_with("begin immediate").await,
            Dialect::Postgres => {
                let mut tx = self.write.begin().await?;
                sqlx::query("select pg_advisory_xact_lock($1)")
                    .bind(POSTGRES_WRITE_LOCK)
                    .execute(&mut *tx)
                    .await?;
                Ok(tx)
            }
        }
    }

    /// Closes both pools (on SQLite, checkpointing the WAL).
    pub async fn close(&self) {
        self.read.close().await;
        self.write.close().await;
    }
}

/// Whether opening may make the registry: a SQLite file, or the tables in a PostgreSQL
/// database (the database itself is always made by PostgreSQL's own tools).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Create {
    IfMissing,
    Never,
}

/// Whether the registry's tables were ever made in this PostgreSQL database.
async fn migrated(pool: &AnyPool) -> anyhow::Result<bool> {
    let count: i64 = sqlx::query_scalar(
        "select count(*) from information_schema.tables where table_name = '_sqlx_migrations'",
    )
    .fetch_one(pool)
    .await
    .context("cannot tell whether the database holds a registry")?;
    Ok(count > 0)
}

async fn open_sqlite(
    path: &Path,
    lock_timeout: Duration,
) -> anyhow::Result<(AnyPool, AnyPool, Dialect)> {
    create_private(path)?;
    let url = sqlite_url(path)?;
    let busy = lock_timeout.as_millis();
    let write = AnyPoolOptions::new()
        .max_connections(1)
        .after_connect(move |conn, _| {
            Box::pin(async move {
                // An acknowledged write must survive power loss: fsync the WAL on every commit.
                // Another process (the CLI, a backup) may hold the write lock for a moment.
                let pragmas = format!(
                    "pragma journal_mode = wal; pragma synchronous = full; \
                     pragma foreign_keys = on; pragma busy_timeout = {busy};"
                );
                sqlx::raw_sql(sqlx::AssertSqlSafe(pragmas)).execute(conn).await.map(drop)
            })
        })
        .after_release(|conn, _| Box::pin(outside_transaction(conn)))
        // A write dropped half-way (its client went away) may have left a BEGIN running.
        .before_acquire(|conn, _| Box::pin(outside_transaction(conn)))
        .connect(&format!("{url}?mode=rwc"))
        .await
        .with_context(|| format!("cannot open the database {}", path.display()))?;
    let read = AnyPoolOptions::new()
        .max_connections(READERS)
        .after_connect(move |conn, _| {
            Box::pin(async move {
                let pragmas = format!("pragma foreign_keys = on; pragma busy_timeout = {busy};");
                sqlx::raw_sql(sqlx::AssertSqlSafe(pragmas)).execute(conn).await.map(drop)
            })
        })
        .connect(&format!("{url}?mode=ro"))
        .await
        .with_context(|| format!("cannot open the database {} for reading", path.display()))?;
    Ok((read, write, Dialect::Sqlite))
}

async fn open_postgres(
    url: &str,
    location: &Location,
    lock_timeout: Duration,
) -> anyhow::Result<(AnyPool, AnyPool, Dialect)> {
    let write = AnyPoolOptions::new()
        .max_connections(1)
        .acquire_timeout(lock_timeout)
        .after_release(|conn, _| Box::pin(outside_transaction(conn)))
        .before_acquire(|conn, _| Box::pin(outside_transaction(conn)))
        .connect(url)
        .await
        .with_context(|| format!("cannot connect to the database {location}"))?;
    let read = AnyPoolOptions::new()
        .max_connections(READERS)
        .acquire_timeout(lock_timeout)
        .connect(url)
        .await
        .with_context(|| format!("cannot connect to the database {location} for reading"))?;
    Ok((read, write, Dialect::Postgres))
}

/// The `sqlite://` URL of `path`, absolute, with the characters a URL would misread escaped.
fn sqlite_url(path: &Path) -> anyhow::Result<String> {
    let absolute = std::path::absolute(path)
        .with_context(|| format!("cannot resolve the database path {}", path.display()))?;
    let text = absolute
        .to_str()
        .with_context(|| format!("the database path {} is not UTF-8", path.display()))?;
    let mut escaped = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '%' => escaped.push_str("%25"),
            '?' => escaped.push_str("%3F"),
            '#' => escaped.push_str("%23"),
            ' ' => escaped.push_str("%20"),
            c => escaped.push(c),
        }
    }
    Ok(format!("sqlite://{escaped}"))
}

/// Whether a write connection may be used again: not when it is stuck inside a transaction
/// (a commit and its rollback both failed, as on a full disk), which would make every later
/// `begin` fail. The pool then closes it and opens a fresh one.
async fn outside_transaction(conn: &mut AnyConnection) -> sqlx::Result<bool> {
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
