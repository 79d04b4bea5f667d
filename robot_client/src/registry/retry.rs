//! How long the robot waits before asking the registry again after it could not be reached:
//! one policy for every loop that retries (following the change feed, claiming a task,
//! finishing one).
//!
//! The waits grow from half a second to ten seconds, so a registry that is away for a while is
//! not asked twice a second by every robot, and they are jittered, so a fleet that lost the
//! registry together (a restart, a Wi-Fi drop) does not come back in lockstep.

use std::time::Duration;

use backon::{BackoffBuilder, ExponentialBuilder};

/// The first wait.
pub const FIRST_WAIT: Duration = Duration::from_millis(500);
/// The longest wait, before jitter.
pub const LONGEST_WAIT: Duration = Duration::from_secs(10);

/// A fresh sequence of waits, endless; start a new one once the registry answers again.
pub fn waits() -> impl Iterator<Item = Duration> + Send {
    ExponentialBuilder::new()
        .with_min_delay(FIRST_WAIT)
        .with_max_delay(LONGEST_WAIT)
        .with_jitter()
        .without_max_times()
        .build()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waits_grow_to_a_bound_and_two_robots_do_not_wait_alike() {
        let first: Vec<Duration> = waits().take(12).collect();
        let second: Vec<Duration> = waits().take(12).collect();
        assert!(first[0] >= FIRST_WAIT && first[0] < 2 * FIRST_WAIT, "{first:?}");
        assert!(first.iter().all(|w| *w < 2 * LONGEST_WAIT), "bounded: {first:?}");
        assert!(first[11] >= LONGEST_WAIT, "grown to the longest wait: {first:?}");
        assert_ne!(first, second, "jittered");
    }
}
