//! Waiting for a condition with a deadline, never for a fixed time.

use std::future::Future;
use std::time::{Duration, Instant};

/// How long any one condition may take before the test fails.
pub const DEADLINE: Duration = Duration::from_secs(15);
/// How often a condition is re-checked.
const POLL: Duration = Duration::from_millis(50);

/// Polls `check` until it yields a value, or gives up with `None` after [`DEADLINE`].
pub async fn within<T, F, Fut>(check: F) -> Option<T>
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    within_for(DEADLINE, check).await
}

/// [`within`] with a deadline of its own, for what is slow by nature (a program's start).
async fn within_for<T, F, Fut>(patience: Duration, mut check: F) -> Option<T>
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

/// Polls `check` until it yields a value; panics after [`DEADLINE`] naming `what`.
pub async fn until<T, F, Fut>(what: &str, check: F) -> T
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    within(check).await.unwrap_or_else(|| panic!("gave up after {DEADLINE:?} waiting for {what}"))
}

/// [`until`] with a deadline of its own, for what is slow by nature (a program's start).
pub async fn until_within<T, F, Fut>(what: &str, patience: Duration, check: F) -> T
where
    F: FnMut() -> Fut,
    Fut: Future<Output = Option<T>>,
{
    within_for(patience, check)
        .await
        .unwrap_or_else(|| panic!("gave up after {patience:?} waiting for {what}"))
}
