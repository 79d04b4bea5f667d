//! Conditional requests (RFC 9110 §13): ETags, `If-None-Match` for reads and creates,
//! `If-Match` for replace and archive.

use std::convert::Infallible;

use axum::extract::FromRequestParts;
use axum::http::header::{IF_MATCH, IF_NONE_MATCH};
use axum::http::request::Parts;
use axum::http::{HeaderMap, HeaderValue};

use crate::error::ApiError;
use crate::store::WriteCondition;

/// The strong ETag of a tag revision.
pub fn tag_etag(revision: i64) -> String {
    format!("\"r{revision}\"")
}

/// The revision an ETag of ours names, if it is one.
fn revision_of(etag: &str) -> Option<i64> {
    etag.strip_prefix("\"r")?.strip_suffix('"')?.parse().ok()
}

/// Reads the precondition of a tag write; `None` when the request has none.
pub fn write_condition(headers: &HeaderMap) -> Result<Option<WriteCondition>, ApiError> {
    if let Some(value) = header_text(headers, IF_MATCH)? {
        if value.trim() == "*" {
            return Ok(Some(WriteCondition::AnyRevision));
        }
        // A tag that is not ours can never match, so an unknown ETag simply fails the match.
        let revisions = etag_list(&value).filter_map(revision_of).collect();
        return Ok(Some(WriteCondition::Revisions(revisions)));
    }
    if let Some(value) = header_text(headers, IF_NONE_MATCH)? {
        if value.trim() == "*" {
            return Ok(Some(WriteCondition::Absent));
        }
        return Err(ApiError::BadRequest(
            "on a write, If-None-Match may only be `*` (create if absent)".into(),
        ));
    }
    Ok(None)
}

/// Whether a GET's `If-None-Match` names the current ETag, so the answer is 304.
pub fn not_modified(headers: &HeaderMap, current_etag: &str) -> bool {
    names(headers.get(IF_NONE_MATCH), current_etag)
}

fn names(if_none_match: Option<&HeaderValue>, current_etag: &str) -> bool {
    let Some(value) = if_none_match.and_then(|v| v.to_str().ok()) else {
        return false;
    };
    value.trim() == "*"
        || etag_list(value).any(|tag| tag.strip_prefix("W/").unwrap_or(tag) == current_etag)
}

/// A GET's `If-None-Match` alone, for a handler that needs no other header (taking the whole
/// `HeaderMap` copies it).
#[derive(Debug)]
pub struct IfNoneMatch(Option<HeaderValue>);

impl IfNoneMatch {
    /// Whether it names the current ETag, so the answer is 304.
    pub fn names(&self, current_etag: &str) -> bool {
        names(self.0.as_ref(), current_etag)
    }
}

impl<S: Send + Sync> FromRequestParts<S> for IfNoneMatch {
    type Rejection = Infallible;

    async fn from_request_parts(parts: &mut Parts, _state: &S) -> Result<Self, Self::Rejection> {
        Ok(Self(parts.headers.get(IF_NONE_MATCH).cloned()))
    }
}

fn etag_list(value: &str) -> impl Iterator<Item = &str> {
    value.split(',').map(str::trim).filter(|tag| !tag.is_empty())
}

fn header_text(
    headers: &HeaderMap,
    name: axum::http::HeaderName,
) -> Result<Option<String>, ApiError> {
    headers
        .get(&name)
        .map(|value| {
            value.to_str().map(str::to_owned).map_err(|_| {
                ApiError::BadRequest(format!("the {name} header is not readable text"))
            })
        })
        .transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn headers(name: &'static str, value: &'static str) -> HeaderMap {
        let mut map = HeaderMap::new();
        map.insert(name, value.parse().unwrap());
        map
    }

    #[test]
    fn reads_conditions() {
        assert_eq!(write_condition(&HeaderMap::new()).unwrap(), None);
        assert_eq!(
            write_condition(&headers("if-none-match", "*")).unwrap(),
            Some(WriteCondition::Absent)
        );
        let cond = write_condition(&headers("if-match", "\"r2\", \"r7\"")).unwrap().unwrap();
        assert!(cond.allows(7) && !cond.allows(3));
        let weak = write_condition(&headers("if-match", "W/\"r2\"")).unwrap().unwrap();
        assert!(!weak.allows(2), "If-Match uses strong comparison");
        assert!(write_condition(&headers("if-none-match", "\"r1\"")).is_err());
    }

    #[test]
    fn not_modified_accepts_weak_and_lists() {
        assert!(not_modified(&headers("if-none-match", "\"r1\", W/\"r4\""), "\"r4\""));
        assert!(!not_modified(&headers("if-none-match", "\"r1\""), "\"r4\""));
    }
}
