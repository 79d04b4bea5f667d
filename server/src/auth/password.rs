//! Login passwords: argon2id hashes in PHC form, the rules a new password must meet, and a
//! verification that costs the same whether or not the user exists.
//!
//! Hashing is deliberately slow (tens of milliseconds), so callers on the async runtime go
//! through [`hash_off_runtime`] and [`verify_off_runtime`]. A password is never logged or stored.

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

/// [`hash`] on the blocking pool, off the async runtime's threads.
pub async fn hash_off_runtime(password: String) -> anyhow::Result<String> {
    tokio::task::spawn_blocking(move || hash(&password)).await?
}

/// [`verify_or_decoy`] on the blocking pool, off the async runtime's threads.
pub async fn verify_off_runtime(password: String, stored: Option<String>) -> anyhow::Result<bool> {
    Ok(tokio::task::spawn_blocking(move || verify_or_decoy(&password, stored.as_deref())).await?)
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
