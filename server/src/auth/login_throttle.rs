//! Slows password guessing: after a few failed logins for a user name (or from a client
//! address), further attempts must wait, twice as long after each new failure, up to a minute.
//!
//! Only password checks pass through here; bearer tokens never do, so robots are never slowed.
//! An attempt made while it must wait is refused without looking at the password, so waiting
//! cannot be skipped by guessing faster. State is in memory: a restart forgets it.

use std::collections::HashMap;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Failures allowed before any waiting: enough for a typo or two on a phone keyboard.
pub const FREE_FAILURES: u32 = 3;
/// The longest wait between attempts.
pub const MAX_WAIT: Duration = Duration::from_secs(60);
/// Failures are forgotten this long after the last one.
const FORGET_AFTER: Duration = Duration::from_secs(15 * 60);
/// Upper bound on remembered keys, so a flood of made-up names cannot grow memory.
const CAPACITY: usize = 10_000;

#[derive(Debug, Clone, Copy)]
struct Failures {
    count: u32,
    last: Instant,
}

impl Failures {
    /// When the next attempt may be made.
    fn next_allowed(&self) -> Instant {
        self.last + wait_after(self.count)
    }
}

/// The key that counts failures for one login name (as typed, when it is not a valid name).
pub fn user_key(name: &str) -> String {
    format!("user:{}", name.trim().to_lowercase())
}

/// The key that counts failures from one client address, whatever names it tries.
pub fn address_key(address: std::net::IpAddr) -> String {
    format!("address:{address}")
}

/// How long to wait after `count` consecutive failures: nothing at first, then 1 s, 2 s, 4 s…
pub fn wait_after(count: u32) -> Duration {
    match count.checked_sub(FREE_FAILURES) {
        None => Duration::ZERO,
        Some(extra) => Duration::from_secs(1u64 << extra.min(6)).min(MAX_WAIT),
    }
}

/// Recent login failures, by key (`user:NAME`, `address:IP`).
#[derive(Debug, Default)]
pub struct LoginThrottle {
    failures: Mutex<HashMap<String, Failures>>,
}

impl LoginThrottle {
    /// How much longer an attempt on these keys must wait; `None` when it may go ahead.
    pub fn must_wait(&self, keys: &[String]) -> Option<Duration> {
        let failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        let now = Instant::now();
        keys.iter()
            .filter_map(|key| failures.get(key))
            .map(|f| f.next_allowed().saturating_duration_since(now))
            .filter(|wait| !wait.is_zero())
            .max()
    }

    /// Records a failed attempt on every key.
    pub fn failed(&self, keys: &[String]) {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        let now = Instant::now();
        if failures.len() + keys.len() > CAPACITY {
            failures.retain(|_, f| now.duration_since(f.last) < FORGET_AFTER);
        }
        if failures.len() + keys.len() > CAPACITY {
            // Under a flood of made-up keys, forget rather than grow without bound.
            failures.clear();
        }
        for key in keys {
            let entry = failures.entry(key.clone()).or_insert(Failures { count: 0, last: now });
            if now.duration_since(entry.last) >= FORGET_AFTER {
                entry.count = 0;
            }
            entry.count = entry.count.saturating_add(1);
            entry.last = now;
        }
    }

    /// A correct password clears the keys' failures.
    pub fn succeeded(&self, keys: &[String]) {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        for key in keys {
            failures.remove(key);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waits_grow_after_the_free_failures_and_are_capped() {
        assert_eq!(wait_after(0), Duration::ZERO);
        assert_eq!(wait_after(FREE_FAILURES - 1), Duration::ZERO);
        assert_eq!(wait_after(FREE_FAILURES), Duration::from_secs(1));
        assert_eq!(wait_after(FREE_FAILURES + 1), Duration::from_secs(2));
        assert_eq!(wait_after(FREE_FAILURES + 40), MAX_WAIT);
    }

    #[test]
    fn failures_on_any_key_slow_down_and_success_clears() {
        let throttle = LoginThrottle::default();
        let keys = vec![user_key("Anna"), address_key([10, 0, 0, 2].into())];
        for _ in 0..FREE_FAILURES - 1 {
            throttle.failed(&keys);
        }
        assert_eq!(throttle.must_wait(&keys), None);
        throttle.failed(&keys);
        assert!(throttle.must_wait(&keys).is_some());
        assert!(throttle.must_wait(&[user_key("anna")]).is_some());
        assert_eq!(throttle.must_wait(&[user_key("bert")]), None);
        throttle.succeeded(&keys);
        assert_eq!(throttle.must_wait(&keys), None);
    }
}
