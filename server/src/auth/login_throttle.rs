//! Slows password guessing: after a few failed logins for a user name (or from a client
//! address), further attempts must wait, twice as long after each new failure, up to a minute.
//!
//! Only password checks pass through here; bearer tokens never do, so robots are never slowed.
//! An attempt made while it must wait is refused without looking at the password, so waiting
//! cannot be skipped by guessing faster; and an attempt is claimed before its password is
//! hashed, one at a time per name and per address, so it cannot be skipped by guessing in
//! parallel either. State is in memory: a restart forgets it.

use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use time::OffsetDateTime;

/// Failures allowed before any waiting: enough for a typo or two on a phone keyboard.
pub const FREE_FAILURES: u32 = 3;
/// Failures allowed from one address, across names: higher, so one person's typos on a shared
/// computer do not make a colleague wait, while a guesser trying many names still does.
pub const ADDRESS_FREE_FAILURES: u32 = 10;
/// The longest wait between attempts.
pub const MAX_WAIT: Duration = Duration::from_secs(60);
/// Failures are forgotten this long after the last one.
const FORGET_AFTER: Duration = Duration::from_secs(15 * 60);
/// Upper bound on remembered keys, so a flood of made-up names cannot grow memory.
const CAPACITY: usize = 10_000;
/// Longest name kept in a key: longer than any valid login name, short enough that 10,000
/// made-up megabyte names cost nothing.
const MAX_KEY_NAME_CHARS: usize = 2 * crate::identity::user_name::MAX_CHARS;
/// What an attempt is told while another one on its name or address is being checked.
pub const BUSY_WAIT: Duration = Duration::from_secs(1);

#[derive(Debug, Clone, Copy)]
struct Failures {
    count: u32,
    last: OffsetDateTime,
}

impl Failures {
    /// When the next attempt on `key` may be made.
    fn next_allowed(&self, key: &str) -> OffsetDateTime {
        let free = if key.starts_with("address:") { ADDRESS_FREE_FAILURES } else { FREE_FAILURES };
        self.last + wait_after(self.count, free)
    }
}

/// The key that counts failures for one login name (as typed, when it is not a valid name).
pub fn user_key(name: &str) -> String {
    let name: String = name.trim().chars().take(MAX_KEY_NAME_CHARS).collect();
    format!("user:{}", name.to_lowercase())
}

/// The key that counts failures from one client address, whatever names it tries.
pub fn address_key(address: std::net::IpAddr) -> String {
    format!("address:{address}")
}

/// How long to wait after `count` consecutive failures of which `free` cost nothing: then
/// 1 s, 2 s, 4 s…
pub fn wait_after(count: u32, free: u32) -> Duration {
    match count.checked_sub(free) {
        None => Duration::ZERO,
        Some(extra) => Duration::from_secs(1u64 << extra.min(6)).min(MAX_WAIT),
    }
}

/// Recent login failures, by key (`user:NAME`, `address:IP`).
#[derive(Debug, Default)]
pub struct LoginThrottle {
    failures: Mutex<HashMap<String, Failures>>,
    /// Keys with an attempt being checked right now.
    in_flight: Mutex<HashSet<String>>,
}

/// A password attempt that may go ahead; its keys take no other attempt until it is dropped.
#[derive(Debug)]
pub struct Attempt {
    throttle: Arc<LoginThrottle>,
    keys: Vec<String>,
}

impl Attempt {
    /// The password was wrong, as found at `now`.
    pub fn failed(self, now: OffsetDateTime) {
        self.throttle.failed(&self.keys, now);
    }

    /// The password was right.
    pub fn succeeded(self) {
        self.throttle.succeeded(&self.keys);
    }
}

impl Drop for Attempt {
    fn drop(&mut self) {
        let mut in_flight = self.throttle.in_flight.lock().unwrap_or_else(|e| e.into_inner());
        for key in &self.keys {
            in_flight.remove(key);
        }
    }
}

impl LoginThrottle {
    /// Claims an attempt on `keys` at `now`, or says how long to wait: while they must wait
    /// after failures, or while another attempt on any of them is being checked.
    pub fn begin(
        self: &Arc<Self>,
        keys: Vec<String>,
        now: OffsetDateTime,
    ) -> Result<Attempt, Duration> {
        if let Some(wait) = self.must_wait(&keys, now) {
            return Err(wait);
        }
        let mut in_flight = self.in_flight.lock().unwrap_or_else(|e| e.into_inner());
        if keys.iter().any(|key| in_flight.contains(key)) {
            return Err(BUSY_WAIT);
        }
        in_flight.extend(keys.iter().cloned());
        Ok(Attempt { throttle: self.clone(), keys })
    }

    /// How much longer after `now` an attempt on these keys must wait; `None` when it may go
    /// ahead.
    fn must_wait(&self, keys: &[String], now: OffsetDateTime) -> Option<Duration> {
        let failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        keys.iter()
            .filter_map(|key| failures.get(key).map(|f| f.next_allowed(key)))
            .filter_map(|allowed| Duration::try_from(allowed - now).ok())
            .filter(|wait| !wait.is_zero())
            .max()
    }

    /// Records a failed attempt on every key at `now`.
    fn failed(&self, keys: &[String], now: OffsetDateTime) {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        if failures.len() + keys.len() > CAPACITY {
            failures.retain(|_, f| now - f.last < FORGET_AFTER);
        }
        if failures.len() + keys.len() > CAPACITY {
            // Under a flood of made-up keys, forget rather than grow without bound.
            failures.clear();
        }
        for key in keys {
            let entry = failures.entry(key.clone()).or_insert(Failures { count: 0, last: now });
            if now - entry.last >= FORGET_AFTER {
                entry.count = 0;
            }
            entry.count = entry.count.saturating_add(1);
            entry.last = now;
        }
    }

    /// A correct password clears the keys' failures.
    fn succeeded(&self, keys: &[String]) {
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
        assert_eq!(wait_after(0, FREE_FAILURES), Duration::ZERO);
        assert_eq!(wait_after(FREE_FAILURES - 1, FREE_FAILURES), Duration::ZERO);
        assert_eq!(wait_after(FREE_FAILURES, FREE_FAILURES), Duration::from_secs(1));
        assert_eq!(wait_after(FREE_FAILURES + 1, FREE_FAILURES), Duration::from_secs(2));
        assert_eq!(wait_after(FREE_FAILURES + 40, FREE_FAILURES), MAX_WAIT);
    }

    #[test]
    fn failures_on_any_key_slow_down_and_success_clears() {
        let throttle = LoginThrottle::default();
        let now = OffsetDateTime::now_utc();
        let keys = vec![user_key("Anna"), address_key([10, 0, 0, 2].into())];
        for _ in 0..FREE_FAILURES - 1 {
            throttle.failed(&keys, now);
        }
        assert_eq!(throttle.must_wait(&keys, now), None);
        throttle.failed(&keys, now);
        assert!(throttle.must_wait(&keys, now).is_some());
        assert!(throttle.must_wait(&[user_key("anna")], now).is_some());
        assert_eq!(throttle.must_wait(&[user_key("bert")], now), None);
        throttle.succeeded(&keys);
        assert_eq!(throttle.must_wait(&keys, now), None);
    }

    #[test]
    fn one_address_guessing_many_names_is_slowed_too() {
        let throttle = LoginThrottle::default();
        let now = OffsetDateTime::now_utc();
        let address = address_key([10, 0, 0, 3].into());
        for n in 0..ADDRESS_FREE_FAILURES {
            let keys = vec![user_key(&format!("name{n}")), address.clone()];
            assert_eq!(throttle.must_wait(&keys, now), None, "attempt {n}");
            throttle.failed(&keys, now);
        }
        assert!(throttle.must_wait(&[user_key("someone else"), address], now).is_some());
    }

    #[test]
    fn one_attempt_at_a_time_per_key() {
        let throttle = Arc::new(LoginThrottle::default());
        let now = OffsetDateTime::now_utc();
        let address = address_key([10, 0, 0, 4].into());
        let first = throttle.begin(vec![user_key("anna"), address.clone()], now).unwrap();
        assert_eq!(throttle.begin(vec![user_key("Anna")], now).unwrap_err(), BUSY_WAIT);
        assert!(throttle.begin(vec![user_key("bert"), address.clone()], now).is_err());
        assert!(throttle.begin(vec![user_key("bert")], now).is_ok());
        first.failed(now);
        assert!(throttle.begin(vec![user_key("anna"), address], now).is_ok(), "claim released");
    }

    #[test]
    fn the_wait_ends_when_its_time_has_passed_and_old_failures_are_forgotten() {
        let throttle = LoginThrottle::default();
        let now = OffsetDateTime::now_utc();
        let keys = vec![user_key("anna")];
        for _ in 0..FREE_FAILURES + 1 {
            throttle.failed(&keys, now);
        }
        assert_eq!(throttle.must_wait(&keys, now), Some(Duration::from_secs(2)));
        assert_eq!(
            throttle.must_wait(&keys, now + Duration::from_millis(1500)),
            Some(Duration::from_millis(500))
        );
        assert_eq!(throttle.must_wait(&keys, now + Duration::from_secs(2)), None);
        let much_later = now + FORGET_AFTER;
        throttle.failed(&keys, much_later);
        assert_eq!(
            throttle.must_wait(&keys, much_later),
            None,
            "one failure after a long pause is free"
        );
    }

    #[test]
    fn keys_of_long_names_are_short() {
        assert!(user_key(&"x".repeat(1 << 20)).len() < 200);
    }
}
