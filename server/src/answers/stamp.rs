//! Times in answers: `OffsetDateTime` in the code, the registry's stored form on the wire
//! (RFC 3339, UTC, milliseconds: `crate::clock::format`). Use as `#[serde(with = "stamp")]`
//! with `#[schemars(with = "stamp::DateTime")]`, or the `option` pair for a time that may be
//! missing.

use schemars::json_schema;
use serde::Serializer;
use time::OffsetDateTime;

use crate::clock;

pub fn serialize<S: Serializer>(at: &OffsetDateTime, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_str(&clock::format(*at))
}

/// `null` for no time.
pub mod option {
    use serde::Serializer;
    use time::OffsetDateTime;

    pub fn serialize<S: Serializer>(
        at: &Option<OffsetDateTime>,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        match at {
            Some(at) => super::serialize(at, serializer),
            None => serializer.serialize_none(),
        }
    }
}

written_schema!(
    /// The schema of a time on the wire.
    DateTime,
    "date_time",
    inline: true,
    json_schema!({ "type": "string", "format": "date-time" })
);

/// A time the store keeps as text, as a moment. The store writes these columns only with
/// `clock::format`, so the text always parses; should a row ever hold something else, the
/// answer says the epoch and the log says which text, rather than failing a whole list.
pub fn stored(text: &str) -> OffsetDateTime {
    clock::parse(text).unwrap_or_else(|| {
        tracing::error!(text, "a stored time is not RFC 3339");
        OffsetDateTime::UNIX_EPOCH
    })
}

/// [`stored`] for a time that may be missing.
pub fn stored_option(text: Option<&str>) -> Option<OffsetDateTime> {
    text.map(stored)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize)]
    struct At {
        #[serde(with = "super")]
        at: OffsetDateTime,
        #[serde(with = "option")]
        until: Option<OffsetDateTime>,
    }

    #[test]
    fn stored_times_go_out_as_they_were_stored() {
        let text = "2026-01-02T03:04:05.120Z";
        let at = At { at: stored(text), until: None };
        assert_eq!(
            serde_json::to_value(&at).unwrap(),
            serde_json::json!({ "at": text, "until": null })
        );
    }
}
