//! Whether the registry can take writes right now: room on the database's disk and the write
//! lock within reach. Liveness (`/healthz`) only says the process answers; this says whether a
//! trial sent now would be stored.

use std::time::Duration;

use super::Db;

/// Less free space than this on the database's file system counts as full: a commit needs
/// room for its WAL frames, and a trial with force samples is a few hundred kilobytes.
pub const MIN_FREE_BYTES: u64 = 1 << 20;
/// How long the check waits for the write lock before calling the database locked, at most:
/// never longer than a write would wait.
const LOCK_WAIT: Duration = Duration::from_secs(2);

/// Why the registry cannot write, in words for the operator.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NotReady {
    #[error(
        "the disk holding the database has {free_bytes} bytes free, less than the {} it needs to \
         take writes; free some space",
        MIN_FREE_BYTES
    )]
    DiskFull { free_bytes: u64 },
    #[error(
        "the database stayed locked for {} s (another process holds its write lock)",
        waited.as_secs()
    )]
    Locked { waited: Duration },
    #[error("the database server cannot be reached: {0}")]
    Unreachable(String),
    #[error("the database cannot be written: {0}")]
    Failing(String),
}

impl Db {
    /// `Ok` when a write made now should succeed.
    pub async fn readiness(&self) -> Result<(), NotReady> {
        // A PostgreSQL server watches its own disk; it answers a write it cannot take with
        // disk_full, which the probe below reports.
        if let Some(file) = self.location.file() {
            let directory = file.parent().filter(|d| !d.as_os_str().is_empty());
            let directory = directory.unwrap_or(std::path::Path::new("."));
            if let Ok(stats) = rustix::fs::statvfs(directory) {
                let free_bytes = stats.f_bavail.saturating_mul(stats.f_frsize);
                if free_bytes < MIN_FREE_BYTES {
                    return Err(NotReady::DiskFull { free_bytes });
                }
            }
        }
        // Taking the write lock and letting go writes nothing. The probe runs to its end on
        // its own, since a BEGIN abandoned half-way would leave the connection in a
        // transaction, and one probe at a time, so a flood of probes cannot crowd out writes.
        let wait = LOCK_WAIT.min(self.lock_timeout);
        let locked = NotReady::Locked { waited: wait };
        let turn = tokio::time::timeout(wait, self.probe.clone().lock_owned())
            .await
            .map_err(|_| locked.clone())?;
        let db = self.clone();
        let probe = tokio::spawn(async move {
            let _turn = turn;
            let tx = db.begin_write().await?;
            tx.rollback().await
        });
        match tokio::time::timeout(wait, probe).await {
            Err(_) => Err(locked),
            Ok(Err(panicked)) => Err(NotReady::Failing(panicked.to_string())),
            Ok(Ok(Err(error))) => match super::Unwritable::of(&error) {
                Some(super::Unwritable::Locked | super::Unwritable::Overloaded) => Err(locked),
                Some(super::Unwritable::Unreachable) => {
                    Err(NotReady::Unreachable(error.to_string()))
                }
                _ => Err(NotReady::Failing(error.to_string())),
            },
            Ok(Ok(Ok(()))) => Ok(()),
        }
    }
}
