//! Database errors that mean "not now" rather than "never": a full disk, a write lock another
//! process holds, no free connection. They are the client's cue to retry (503 with
//! `Retry-After`), not a bug (500).

/// Why the database could not take a write just now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unwritable {
    /// The disk (or the file system holding the database) has no room left.
    DiskFull,
    /// Another connection or process holds the lock longer than the busy timeout.
    Locked,
    /// Every connection stayed busy for the pool's whole acquire timeout.
    Overloaded,
    /// The database server cannot be reached (PostgreSQL restarting or failing over).
    Unreachable,
}

// SQLite's primary result codes (the low byte of an extended code).
const SQLITE_BUSY: i64 = 5;
const SQLITE_LOCKED: i64 = 6;
const SQLITE_FULL: i64 = 13;

impl Unwritable {
    /// The transient condition behind `error`, if it is one.
    pub fn of(error: &sqlx::Error) -> Option<Self> {
        match error {
            sqlx::Error::PoolTimedOut => Some(Self::Overloaded),
            // PostgreSQL went away (restarting, failing over): the next connection may work.
            sqlx::Error::Io(_) | sqlx::Error::PoolClosed => Some(Self::Unreachable),
            sqlx::Error::Database(db) => {
                if let Some(postgres) = db.try_downcast_ref::<sqlx::postgres::PgDatabaseError>() {
                    return Self::of_sqlstate(postgres.code());
                }
                let code: i64 = db.code()?.parse().ok()?;
                match code & 0xff {
                    SQLITE_FULL => Some(Self::DiskFull),
                    SQLITE_BUSY | SQLITE_LOCKED => Some(Self::Locked),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// PostgreSQL's SQLSTATE classes that mean "not now".
    fn of_sqlstate(code: &str) -> Option<Self> {
        match code {
            // disk_full, insufficient_resources, out_of_memory
            "53100" | "53000" | "53200" => Some(Self::DiskFull),
            // lock_not_available, serialization_failure, deadlock_detected
            "55P03" | "40001" | "40P01" => Some(Self::Locked),
            // too_many_connections
            "53300" => Some(Self::Overloaded),
            // admin_shutdown, crash_shutdown, cannot_connect_now, connection exceptions
            "57P01" | "57P02" | "57P03" => Some(Self::Unreachable),
            _ if code.starts_with("08") => Some(Self::Unreachable),
            _ => None,
        }
    }

    /// What a client is told (it changed nothing; retry).
    pub fn advice(self) -> &'static str {
        match self {
            Self::DiskFull => {
                "the registry cannot store anything right now: its disk is full. Nothing was \
                 changed; retry after the administrator has freed some space"
            }
            Self::Locked => {
                "the registry's database is locked by another process (a backup or a command \
                 line tool); nothing was changed, retry in a few seconds"
            }
            Self::Overloaded => {
                "the registry is too busy to take this request; nothing was changed, retry in \
                 a few seconds"
            }
            Self::Unreachable => {
                "the registry cannot reach its database right now; nothing was changed, retry \
                 in a few seconds"
            }
        }
    }

    /// Logs the condition for the operator, once per failed request.
    pub fn log(self, error: &sqlx::Error) {
        match self {
            Self::DiskFull => tracing::error!(
                %error,
                "the disk holding the database is full: writes are refused with 503 until \
                 space is freed"
            ),
            Self::Locked => tracing::warn!(%error, "the database stayed locked; answered 503"),
            Self::Overloaded => {
                tracing::warn!(%error, "no database connection came free; answered 503")
            }
            Self::Unreachable => {
                tracing::warn!(%error, "the database server cannot be reached; answered 503")
            }
        }
    }
}
