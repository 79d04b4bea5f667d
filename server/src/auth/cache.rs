//! The token cache on the hot path: a hash look-up in memory, the database only on a miss.
//!
//! Entries are re-checked against the database after [`RECHECK_AFTER`], which bounds how long a
//! token revoked by another process (the CLI) keeps working.

use std::collections::HashMap;
use std::sync::{Arc, RwLock};
use std::time::Duration;

use time::OffsetDateTime;

use super::principal::Principal;

/// How long a cached positive look-up is trusted.
pub const RECHECK_AFTER: Duration = Duration::from_secs(2);

/// Upper bound on cached tokens, so a flood of distinct bogus tokens cannot grow memory.
const CAPACITY: usize = 4096;

#[derive(Debug)]
struct Cached {
    principal: Arc<Principal>,
    checked_at: OffsetDateTime,
    /// When the token stops working, if it expires.
    expires_at: Option<OffsetDateTime>,
}

impl Cached {
    /// Checked less than [`RECHECK_AFTER`] before `now`; a clock set back does not stretch
    /// that.
    fn fresh_at(&self, now: OffsetDateTime) -> bool {
        let age = now - self.checked_at;
        !age.is_negative() && age < RECHECK_AFTER
    }
}

#[derive(Debug, Default)]
pub struct TokenCache {
    /// By the token's SHA-256 ([`crate::identity::secret::digest`]).
    entries: RwLock<HashMap<[u8; 32], Cached>>,
}

impl TokenCache {
    /// The principal for a token's digest, when it was confirmed live shortly before `now`.
    pub fn get(&self, digest: &[u8; 32], now: OffsetDateTime) -> Option<Arc<Principal>> {
        let entries = self.entries.read().unwrap_or_else(|e| e.into_inner());
        let cached = entries.get(digest)?;
        let live = cached.expires_at.is_none_or(|at| now < at);
        (cached.fresh_at(now) && live).then(|| cached.principal.clone())
    }

    /// Remembers a token confirmed live at `now`.
    pub fn insert(
        &self,
        digest: [u8; 32],
        principal: Arc<Principal>,
        now: OffsetDateTime,
        expires_at: Option<OffsetDateTime>,
    ) {
        let mut entries = self.entries.write().unwrap_or_else(|e| e.into_inner());
        if entries.len() >= CAPACITY {
            entries.retain(|_, cached| cached.fresh_at(now));
        }
        entries.insert(digest, Cached { principal, checked_at: now, expires_at });
    }

    /// Forgets every cached token, e.g. after a revocation through the API.
    pub fn clear(&self) {
        self.entries.write().unwrap_or_else(|e| e.into_inner()).clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identity::Role;

    fn nurse() -> Arc<Principal> {
        Arc::new(Principal { role: Role::Caretaker, name: "nurse".into(), robot: None })
    }

    #[test]
    fn a_token_is_trusted_from_memory_only_briefly_and_never_past_its_expiry() {
        let cache = TokenCache::default();
        let checked = time::macros::datetime!(2026-12-05 10:00 UTC);
        let expires = checked + Duration::from_secs(1);
        cache.insert([1; 32], nurse(), checked, None);
        cache.insert([2; 32], nurse(), checked, Some(expires));
        assert!(cache.get(&[1; 32], checked + Duration::from_millis(1999)).is_some());
        assert!(cache.get(&[1; 32], checked + RECHECK_AFTER).is_none(), "checked again");
        assert!(cache.get(&[1; 32], checked - Duration::from_secs(3600)).is_none(), "set back");
        assert!(cache.get(&[2; 32], checked).is_some());
        assert!(cache.get(&[2; 32], expires).is_none(), "expired");
    }
}
