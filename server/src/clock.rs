//! Timestamps as the registry stores and returns them: RFC 3339, UTC, millisecond precision.

use time::format_description::well_known::Rfc3339;
use time::{OffsetDateTime, UtcOffset};

/// The current time, formatted for storage and JSON.
pub fn now() -> String {
    format(OffsetDateTime::now_utc())
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
}
