//! Time in the registry: the one clock every decision reads (leases, expiry, throttles,
//! sessions, presence), and timestamps as the registry stores and returns them: RFC 3339, UTC,
//! millisecond precision.

use std::sync::Arc;

use time::format_description::well_known::Rfc3339;
use time::{OffsetDateTime, UtcOffset};
use tokio::sync::watch;

/// Where the registry's time comes from: the system clock when serving, a [`ManualClock`] in
/// tests, which move it forward instead of waiting for a lease or a throttle to run out.
#[derive(Debug, Clone, Default)]
pub enum Clock {
    #[default]
    System,
    Manual(ManualClock),
}

impl Clock {
    pub fn now(&self) -> OffsetDateTime {
        match self {
            Self::System => OffsetDateTime::now_utc(),
            Self::Manual(clock) => clock.now(),
        }
    }

    /// Hears of the clock being moved, so work that waits for a time (the lease sweep) runs
    /// as soon as a test moves past it; the system clock is never moved.
    pub fn moves(&self) -> Moves {
        match self {
            Self::System => Moves(None),
            Self::Manual(clock) => Moves(Some(clock.at.subscribe())),
        }
    }
}

/// Each time a [`ManualClock`] moves, from [`Clock::moves`].
#[derive(Debug)]
pub struct Moves(Option<watch::Receiver<OffsetDateTime>>);

impl Moves {
    /// Returns once the clock has moved since the last call; never for the system clock.
    pub async fn next(&mut self) {
        if let Some(moved) = &mut self.0
            && moved.changed().await.is_ok()
        {
            return;
        }
        // The system clock, or a manual clock that is gone: nothing will move it.
        std::future::pending().await
    }
}

impl From<ManualClock> for Clock {
    fn from(clock: ManualClock) -> Self {
        Self::Manual(clock)
    }
}

/// A clock that stands still until it is moved: what a test sees run out ran out because the
/// test moved time past it, never because the machine was slow. Clones share one time.
#[derive(Debug, Clone)]
pub struct ManualClock {
    at: Arc<watch::Sender<OffsetDateTime>>,
}

impl Default for ManualClock {
    /// Standing at the system clock's time when made (to the millisecond, as stored).
    fn default() -> Self {
        let now = OffsetDateTime::now_utc();
        Self::starting_at(now.replace_millisecond(now.millisecond()).unwrap_or(now))
    }
}

impl ManualClock {
    pub fn starting_at(at: OffsetDateTime) -> Self {
        Self { at: Arc::new(watch::Sender::new(at)) }
    }

    pub fn now(&self) -> OffsetDateTime {
        *self.at.borrow()
    }

    /// Moves the clock forward by `by`, as if that much time had passed.
    pub fn advance(&self, by: std::time::Duration) {
        self.at.send_modify(|at| *at += by);
    }
}

/// The system clock's time, for stamps that only record when something was written and that
/// nothing decides by (an event, an edit, a token minted): every decision reads a [`Clock`].
pub fn recorded_now() -> OffsetDateTime {
    OffsetDateTime::now_utc()
}

/// Fixed-width, so stored timestamps sort correctly as text.
const STORED: &[time::format_description::FormatItem<'static>] = time::macros::format_description!(
    "[year]-[month]-[day]T[hour]:[minute]:[second].[subsecond digits:3]Z"
);

/// Formats a moment in UTC with milliseconds.
pub fn format(at: OffsetDateTime) -> String {
    at.to_offset(UtcOffset::UTC).format(STORED).unwrap_or_default()
}

/// Parses an RFC 3339 timestamp.
pub fn parse(text: &str) -> Option<OffsetDateTime> {
    OffsetDateTime::parse(text, &Rfc3339).ok()
}

/// Serde for a moment in the stored form (`#[serde(with = "clock::stored")]`).
pub mod stored {
    use serde::{Deserialize, Deserializer, Serializer};
    use time::OffsetDateTime;

    pub fn serialize<S: Serializer>(at: &OffsetDateTime, to: S) -> Result<S::Ok, S::Error> {
        to.serialize_str(&super::format(*at))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(from: D) -> Result<OffsetDateTime, D::Error> {
        let text = String::deserialize(from)?;
        super::parse(&text).ok_or_else(|| serde::de::Error::custom("not an RFC 3339 timestamp"))
    }

    /// The same for a moment that may be absent (`null`).
    pub mod option {
        use serde::{Deserialize, Deserializer, Serializer};
        use time::OffsetDateTime;

        pub fn serialize<S: Serializer>(
            at: &Option<OffsetDateTime>,
            to: S,
        ) -> Result<S::Ok, S::Error> {
            match at {
                Some(at) => super::serialize(at, to),
                None => to.serialize_none(),
            }
        }

        pub fn deserialize<'de, D: Deserializer<'de>>(
            from: D,
        ) -> Result<Option<OffsetDateTime>, D::Error> {
            match Option::<String>::deserialize(from)? {
                None => Ok(None),
                Some(text) => crate::clock::parse(&text)
                    .map(Some)
                    .ok_or_else(|| serde::de::Error::custom("not an RFC 3339 timestamp")),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stored_times_sort_as_text() {
        let early = format(time::macros::datetime!(2026-01-02 03:04:05.1 UTC));
        let late = format(time::macros::datetime!(2026-01-02 03:04:05.25 +01:00));
        assert_eq!(early, "2026-01-02T03:04:05.100Z");
        assert!(format(time::macros::datetime!(2026-01-02 03:04:05 UTC)) < early);
        assert!(parse(&late).is_some());
    }

    #[test]
    fn a_manual_clock_moves_when_told() {
        let start = time::macros::datetime!(2026-01-02 03:04:05.1 UTC);
        let manual = ManualClock::starting_at(start);
        let clock = Clock::from(manual.clone());
        assert_eq!(clock.now(), start, "it stands still");
        manual.advance(std::time::Duration::from_secs(3600));
        assert_eq!(clock.now(), start + time::Duration::HOUR);
    }

    #[tokio::test]
    async fn moving_a_manual_clock_is_heard() {
        let manual = ManualClock::default();
        let mut moves = Clock::from(manual.clone()).moves();
        manual.advance(std::time::Duration::from_secs(1));
        tokio::time::timeout(std::time::Duration::from_secs(5), moves.next())
            .await
            .expect("the move is heard");
    }
}
