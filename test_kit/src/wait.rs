//! Waiting for a condition with a deadline, never for a fixed time.
//!
//! This is the one place of the test suites that pauses: between two looks at a condition.
//! Everything else waits for what it needs through here (clippy's `disallowed_methods` bans
//! sleeping elsewhere).
#![allow(clippy::disallowed_methods)] // the pause between two looks at the condition

use std::future::Future;
use std::time::{Duration, Instant};

/// How long any one condition may take before the test fails.
pub const DEADLINE: Duration = Duration::from_secs(15);
/// How often a condition is re-checked.
const POLL: Duration = Duration::from_millis(20);

/// Polls `check` until it yields a value; panics after `deadline`, naming `reason` (what the
/// test waited for).
pub async fn wait_until<T, F, Fut>(deadline: Duration, reason: &str, check: F) -> T
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    try_wait_until(deadline, check)
        .await
        .unwrap_or_else(|| panic!("gave up after {deadline:?} waiting for {reason}"))
}

/// [`wait_until`] for a condition that is only true or false.
pub async fn wait_for<F, Fut>(deadline: Duration, reason: &str, mut check: F)
where
    F: FnMut() -> Fut,
    Fut: Future<Output = bool>,
{
    let check = || {
        let holds = check();
        async move { holds.await.then_some(()) }
    };
    wait_until(deadline, reason, check).await
}

/// [`wait_until`] for code without a runtime (threads, blocking I/O): polls `check` on this
/// thread.
pub fn wait_until_blocking<T>(
    deadline: Duration,
    reason: &str,
    mut check: impl FnMut() -> Option<T>,
) -> T {
    let end = Instant::now() + deadline;
    loop {
        if let Some(value) = check() {
            return value;
        }
        assert!(Instant::now() < end, "gave up after {deadline:?} waiting for {reason}");
        std::thread::sleep(POLL);
    }
}

/// Polls `check` until it yields a value, or gives up with `None` after [`DEADLINE`], for a
/// test that asserts on the absence itself.
pub async fn within<T, F, Fut>(check: F) -> Option<T>
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    try_wait_until(DEADLINE, check).await
}

/// Polls `check` until it yields a value, or gives up with `None` after `patience`, for a
/// test whose failure message says what it saw at the end (a log, say).
pub async fn try_wait_until<T, F, Fut>(patience: Duration, mut check: F) -> Option<T>
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    let deadline = Instant::now() + patience;
    loop {
        if let Some(value) = check().await {
            return Some(value);
        }
        if Instant::now() >= deadline {
            return None;
        }
        tokio::time::sleep(POLL).await;
    }
}

/// [`wait_until`] with the usual [`DEADLINE`].
pub async fn until<T, F, Fut>(what: &str, check: F) -> T
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    wait_until(DEADLINE, what, check).await
}
