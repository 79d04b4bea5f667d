//! Login passwords: argon2id hashes in PHC form, the rules a new password must meet, and a
//! verification that costs the same whether or not the user exists.
//!
//! Hashing is deliberately slow (tens of milliseconds) and works in 19 MiB. On the server it
//! runs only on a few hashing threads ([`hashing_threads`]), each of which allocates its 19 MiB
//! once and hashes every password in that same memory: however many people log in, and
//! whatever the allocator does with freed memory, hashing never holds more than the threads'
//! blocks. Callers on the async runtime go through [`hash_off_runtime`] and
//! [`verify_off_runtime`], which queue [`MAX_WAITING_HASHES`] jobs at most (queued jobs hold
//! no hashing memory); a login beyond is told to retry. A password is never logged or stored.

use std::sync::LazyLock;
use std::sync::atomic::{AtomicUsize, Ordering};

use argon2::password_hash::phc::{Output, ParamsString, PasswordHash, Salt};
use argon2::{Algorithm, Argon2, Block, Params, Version};

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

/// The memory one hash works in, allocated once per hashing thread and reused for every hash
/// it computes.
pub struct HashMemory(Vec<Block>);

/// How many [`HashMemory`] regions the hashing threads have allocated; it stays at
/// [`hashing_threads`] however many passwords the server checks.
static THREAD_MEMORY_REGIONS: AtomicUsize = AtomicUsize::new(0);

impl HashMemory {
    /// Room for the default cost (19 MiB).
    pub fn new() -> Self {
        Self(vec![Block::new(); Params::DEFAULT.block_count()])
    }

    /// The regions the hashing threads have allocated so far.
    pub fn allocated_for_hashing_threads() -> usize {
        THREAD_MEMORY_REGIONS.load(Ordering::Relaxed)
    }

    /// The first `blocks` blocks; `None` when a hash asks for more than the region holds.
    fn blocks(&mut self, blocks: usize) -> Option<&mut [Block]> {
        self.0.get_mut(..blocks)
    }
}

impl std::fmt::Debug for HashMemory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "HashMemory({} KiB)", self.0.len())
    }
}

impl Default for HashMemory {
    fn default() -> Self {
        Self::new()
    }
}

/// The argon2id PHC string of a password, with a fresh random salt and the crate's default cost
/// (19 MiB, 2 passes: OWASP's recommendation), computed in `memory`.
pub fn hash_in(memory: &mut HashMemory, password: &str) -> anyhow::Result<String> {
    let cannot = |error: &dyn std::fmt::Display| anyhow::anyhow!("cannot hash a password: {error}");
    let argon2 = Argon2::default();
    let salt = argon2::password_hash::try_generate_salt().map_err(|e| cannot(&e))?;
    let mut output = [0u8; Params::DEFAULT_OUTPUT_LEN];
    let blocks = memory.blocks(argon2.params().block_count()).expect("sized for the default");
    argon2
        .hash_password_into_with_memory(password.as_bytes(), &salt, &mut output, blocks)
        .map_err(|e| cannot(&e))?;
    let phc = PasswordHash {
        algorithm: Algorithm::default().ident(),
        version: Some(Version::default().into()),
        params: ParamsString::try_from(argon2.params()).map_err(|e| cannot(&e))?,
        salt: Some(Salt::new(&salt).map_err(|e| cannot(&e))?),
        hash: Some(Output::new(&output).map_err(|e| cannot(&e))?),
    };
    Ok(phc.to_string())
}

/// [`hash_in`] in memory of its own, for a one-off hash (the command line's `user add`).
pub fn hash(password: &str) -> anyhow::Result<String> {
    hash_in(&mut HashMemory::new(), password)
}

/// Whether `password` matches a stored PHC string, computed in `memory`; a malformed stored
/// hash, or one asking for more memory than the default cost, never matches.
pub fn verify_in(memory: &mut HashMemory, password: &str, stored: &str) -> bool {
    let Ok(phc) = PasswordHash::new(stored) else { return false };
    let (Some(salt), Some(expected)) = (&phc.salt, &phc.hash) else { return false };
    let (Ok(algorithm), Ok(params)) =
        (Algorithm::try_from(phc.algorithm.as_str()), Params::try_from(&phc))
    else {
        return false;
    };
    let version = match phc.version.map(Version::try_from).transpose() {
        Ok(version) => version.unwrap_or_default(),
        Err(_) => return false,
    };
    let Some(blocks) = memory.blocks(params.block_count()) else {
        tracing::warn!(
            m_cost = params.m_cost(),
            "a stored password hash asks for more memory than the registry hashes with"
        );
        return false;
    };
    let mut output = [0u8; Output::MAX_LENGTH];
    let output = &mut output[..expected.len()];
    Argon2::new(algorithm, version, params)
        .hash_password_into_with_memory(password.as_bytes(), salt.as_ref(), output, blocks)
        .is_ok_and(|()| Output::new(output).is_ok_and(|computed| computed == *expected))
}

/// [`verify_in`] in memory of its own.
pub fn verify(password: &str, stored: &str) -> bool {
    verify_in(&mut HashMemory::new(), password, stored)
}

/// A hash no password is checked against for real: verifying against it when the user does not
/// exist makes "no such user" take as long as "wrong password", so timing reveals no names.
static DECOY: LazyLock<String> =
    LazyLock::new(|| hash("decoy password never used").unwrap_or_default());

/// [`verify_in`] against the user's hash, or against the decoy when there is no such user.
pub fn verify_or_decoy_in(memory: &mut HashMemory, password: &str, stored: Option<&str>) -> bool {
    match stored {
        Some(stored) => verify_in(memory, password, stored),
        None => {
            verify_in(memory, password, &DECOY);
            false
        }
    }
}

/// Password hashes computed at once, at most: each holds its 19 MiB for good.
pub const MAX_CONCURRENT_HASHES: usize = 4;
/// Hashes queued beyond the running ones, at most; a login beyond is told to retry (503).
pub const MAX_WAITING_HASHES: usize = 16;

/// The hashing threads: one per core, at most [`MAX_CONCURRENT_HASHES`] (more than the cores
/// would only hold more memory, not hash faster).
pub fn hashing_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from).min(MAX_CONCURRENT_HASHES)
}

/// Every hash computer is busy and the queue is full.
#[derive(Debug, thiserror::Error)]
#[error("the registry is checking as many passwords as it can; retry in a moment")]
pub struct HashingBusy;

type HashJob = Box<dyn FnOnce(&mut HashMemory) + Send>;

/// The queue of the hashing threads. A few long-lived threads, rather than the runtime's
/// blocking pool, each owning the memory it hashes in: the memory for hashing is allocated
/// [`hashing_threads`] times in the life of the server, never per password.
static HASHERS: LazyLock<std::sync::mpsc::SyncSender<HashJob>> = LazyLock::new(|| {
    let (queue, jobs) = std::sync::mpsc::sync_channel::<HashJob>(MAX_WAITING_HASHES);
    let jobs = std::sync::Arc::new(std::sync::Mutex::new(jobs));
    for n in 0..hashing_threads() {
        let jobs = jobs.clone();
        let spawned =
            std::thread::Builder::new().name(format!("password-hash-{n}")).spawn(move || {
                // Allocated at the first password, so a server nobody logs in to never holds it.
                let mut memory: Option<HashMemory> = None;
                loop {
                    let job = jobs.lock().unwrap_or_else(|e| e.into_inner()).recv();
                    match job {
                        Ok(job) => job(memory.get_or_insert_with(|| {
                            THREAD_MEMORY_REGIONS.fetch_add(1, Ordering::Relaxed);
                            HashMemory::new()
                        })),
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

/// Runs `work` on a hashing thread, in that thread's memory, or refuses at once when the queue
/// is full.
async fn hashing<T: Send + 'static>(
    work: impl FnOnce(&mut HashMemory) -> T + Send + 'static,
) -> anyhow::Result<T> {
    let (done, result) = tokio::sync::oneshot::channel();
    let job: HashJob = Box::new(move |memory| {
        let _ = done.send(work(memory));
    });
    HASHERS.try_send(job).map_err(|_| HashingBusy)?;
    Ok(result.await?)
}

/// [`hash_in`] on a hashing thread, off the async runtime's threads.
pub async fn hash_off_runtime(password: String) -> anyhow::Result<String> {
    hashing(move |memory| hash_in(memory, &password)).await?
}

/// [`verify_or_decoy_in`] on a hashing thread, off the async runtime's threads.
pub async fn verify_off_runtime(password: String, stored: Option<String>) -> anyhow::Result<bool> {
    hashing(move |memory| verify_or_decoy_in(memory, &password, stored.as_deref())).await
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
        assert!(!verify_or_decoy_in(&mut HashMemory::new(), "correct horse", None));
    }

    #[test]
    fn hashes_of_the_crate_verify_here_and_ours_there() {
        use argon2::password_hash::{PasswordHasher, PasswordVerifier};
        let theirs = Argon2::default().hash_password(b"correct horse").unwrap().to_string();
        assert!(verify("correct horse", &theirs));
        assert!(!verify("correct hors", &theirs));
        let ours = PasswordHash::new(&hash("correct horse").unwrap()).unwrap().to_string();
        let ours = PasswordHash::new(&ours).unwrap();
        assert!(Argon2::default().verify_password(b"correct horse", &ours).is_ok());
    }

    #[test]
    fn a_stored_hash_asking_for_more_memory_never_matches() {
        let greedy = Params::new(Params::DEFAULT_M_COST * 2, 1, 1, None).unwrap();
        let stored = argon2::password_hash::CustomizedPasswordHasher::hash_password_customized(
            &Argon2::default(),
            b"correct horse",
            b"sixteen byte slt",
            None,
            None,
            greedy,
        )
        .unwrap()
        .to_string();
        assert!(!verify("correct horse", &stored));
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn many_passwords_checked_at_once_hash_in_the_threads_own_memory() {
        let stored = hash("correct horse").unwrap();
        let (mut right, mut wrong) = (0, 0);
        // Waves as large as the queue, so every check runs and none is told to retry.
        for _ in 0..5 {
            let checks = (0..MAX_WAITING_HASHES).map(|n| {
                let password = if n % 2 == 0 { "correct horse" } else { "wrong horse" };
                tokio::spawn(verify_off_runtime(password.into(), Some(stored.clone())))
            });
            for check in checks.collect::<Vec<_>>() {
                match check.await.unwrap().unwrap() {
                    true => right += 1,
                    false => wrong += 1,
                }
            }
        }
        assert_eq!((right, wrong), (40, 40));
        let regions = HashMemory::allocated_for_hashing_threads();
        assert!(regions <= hashing_threads(), "{regions} memory regions for 80 hashes");
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
