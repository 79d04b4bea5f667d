//! Login passwords: argon2id hashes in PHC form, the rules a new password must meet, and a
//! verification that costs the same whether or not the user exists.
//!
//! Hashing is deliberately slow (tens of milliseconds) and takes 19 MiB, so callers on the async
//! runtime go through [`hash_off_runtime`] and [`verify_off_runtime`], which run at most
//! [`MAX_CONCURRENT_HASHES`] at once and queue [`MAX_WAITING_HASHES`] more: many logins at the
//! same moment wait their turn or are told to retry instead of taking memory without bound. A password is never logged or stored.

use std::sync::LazyLock;

use argon2::Argon2;
use argon2::password_hash::phc::PasswordHash;
use argon2::password_hash::{PasswordHasher, PasswordVerifier};

/// Shortest password accepted, in characters (NIST SP 800-63B's floor).
pub const MIN_CHARS: usize = 8;
/// Longest password accepted, in bytes, so one request cannot make the server hash megabytes.
pub const MAX_BYTES: usize = 256;

/// Why a proposed password is refused, worded for the person choosing it.
pub fn problem(password: &str) -> Option<String> {
    if password.chars().count() < MIN_CHARS {
        Some(format!("a password needs at least {MIN_CHARS} characters"))
    } else if password.len() > MAX_BYTES {
        Some(format!("a password may have at most {MAX_BYTES} bytes"))
    } else if password.trim().is_empty() {
        Some("a password cannot be only spaces".into())
    } else {
        None
    }
}

/// The argon2id PHC string of a password, with a fresh random salt and the crate's default cost
/// (19 MiB, 2 passes: OWASP's recommendation).
pub fn hash(password: &str) -> anyhow::Result<String> {
    Argon2::default()
        .hash_password(password.as_bytes())
        .map(|hash| hash.to_string())
        .map_err(|error| anyhow::anyhow!("cannot hash a password: {error}"))
}

/// Whether `password` matches a stored PHC string; a malformed stored hash never matches.
pub fn verify(password: &str, stored: &str) -> bool {
    PasswordHash::new(stored)
        .is_ok_and(|hash| Argon2::default().verify_password(password.as_bytes(), &hash).is_ok())
}

/// A hash no password is checked against for real: verifying against it when the user does not
/// exist makes "no such user" take as long as "wrong password", so timing reveals no names.
static DECOY: LazyLock<String> =
    LazyLock::new(|| hash("decoy password never used").unwrap_or_default());

/// [`verify`] against the user's hash, or against the decoy when there is no such user.
pub fn verify_or_decoy(password: &str, stored: Option<&str>) -> bool {
    match stored {
        Some(stored) => verify(password, stored),
        None => {
            verify(password, &DECOY);
            false
        }
    }
}

/// Password hashes computed at once, at most (each holds 19 MiB while it runs).
pub const MAX_CONCURRENT_HASHES: usize = 4;
/// Hashes queued beyond the running ones, at most; a login beyond is told to retry (503).
pub const MAX_WAITING_HASHES: usize = 16;

/// Every hash computer is busy and the queue is full.
#[derive(Debug, thiserror::Error)]
#[error("the registry is checking as many passwords as it can; retry in a moment")]
pub struct HashingBusy;

type HashJob = Box<dyn FnOnce() + Send>;

/// The queue of the hashing threads. A few long-lived threads, rather than the runtime's
/// blocking pool, so that the memory each hash leaves in its thread's allocator is kept by
/// [`MAX_CONCURRENT_HASHES`] threads, not by however many the pool grew to.
static HASHERS: LazyLock<std::sync::mpsc::SyncSender<HashJob>> = LazyLock::new(|| {
    let (queue, jobs) = std::sync::mpsc::sync_channel::<HashJob>(MAX_WAITING_HASHES);
    let jobs = std::sync::Arc::new(std::sync::Mutex::new(jobs));
    for n in 0..MAX_CONCURRENT_HASHES {
        let jobs = jobs.clone();
        let spawned =
            std::thread::Builder::new().name(format!("password-hash-{n}")).spawn(move || {
                loop {
                    let job = jobs.lock().unwrap_or_else(|e| e.into_inner()).recv();
                    match job {
                        Ok(job) => job(),
                        Err(_) => return,
                    }
                }
            });
        if let Err(error) = spawned {
            tracing::error!(%error, "cannot start a password hashing thread");
        }
    }
    queue
});

/// Runs `work` on a hashing thread, or refuses at once when the queue is full.
async fn hashing<T: Send + 'static>(
    work: impl FnOnce() -> T + Send + 'static,
) -> anyhow::Result<T> {
    let (done, result) = tokio::sync::oneshot::channel();
    let job: HashJob = Box::new(move || {
        let _ = done.send(work());
    });
    HASHERS.try_send(job).map_err(|_| HashingBusy)?;
    Ok(result.await?)
}

/// [`hash`] on a hashing thread, off the async runtime's threads.
pub async fn hash_off_runtime(password: String) -> anyhow::Result<String> {
    hashing(move || hash(&password)).await?
}

/// [`verify_or_decoy`] on a hashing thread, off the async runtime's threads.
pub async fn verify_off_runtime(password: String, stored: Option<String>) -> anyhow::Result<bool> {
    hashing(move || verify_or_decoy(&password, stored.as_deref())).await
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hashes_are_salted_argon2id_and_verify() {
        let (a, b) = (hash("correct horse").unwrap(), hash("correct horse").unwrap());
        assert!(a.starts_with("$argon2id$"), "{a}");
        assert_ne!(a, b, "each hash has its own salt");
        assert!(!a.contains("correct horse"));
        assert!(verify("correct horse", &a));
        assert!(!verify("correct hors", &a));
        assert!(!verify("correct horse", "not a phc string"));
        assert!(!verify_or_decoy("correct horse", None));
    }

    #[test]
    fn password_rules() {
        assert!(problem("short").is_some());
        assert!(problem("        ").is_some());
        assert!(problem(&"x".repeat(MAX_BYTES + 1)).is_some());
        assert!(problem("long enough").is_none());
        assert!(problem("ünïcödé!").is_none(), "characters, not bytes, count toward the minimum");
    }
}
