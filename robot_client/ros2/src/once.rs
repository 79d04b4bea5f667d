//! Logging a kind of bad input once: a camera sending the wrong encoding at 30 Hz would
//! otherwise bury every other line of the log.

use std::collections::HashSet;
use std::sync::Mutex;

use crate::input_error::InputError;

/// Remembers which kinds of trouble were already reported.
#[derive(Debug, Default)]
pub struct LogOnce {
    seen: Mutex<HashSet<(&'static str, &'static str)>>,
}

impl LogOnce {
    /// Warns about `error` on `topic` unless that kind of trouble on that topic was reported
    /// before; returns whether it logged.
    pub fn warn(&self, topic: &'static str, error: &InputError) -> bool {
        let first =
            self.seen.lock().unwrap_or_else(|e| e.into_inner()).insert((topic, error.kind()));
        if first {
            tracing::warn!(topic, "{error} (ignored; said once)");
        }
        first
    }

    /// Forgets the trouble reported on `topic` once its input is good again, so a relapse is
    /// reported too.
    pub fn recovered(&self, topic: &'static str) {
        self.seen.lock().unwrap_or_else(|e| e.into_inner()).retain(|(t, _)| *t != topic);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_trouble_is_said_once_and_again_after_recovery() {
        let once = LogOnce::default();
        let error = InputError::ImageEncoding("mono16".into());
        assert!(once.warn("/camera/image_raw", &error));
        assert!(!once.warn("/camera/image_raw", &error));
        assert!(once.warn("/points", &InputError::CloudBigEndian));
        once.recovered("/camera/image_raw");
        assert!(once.warn("/camera/image_raw", &error));
        assert!(!once.warn("/points", &InputError::CloudBigEndian));
    }
}
