//! Conditional requests (RFC 9110 §13): ETags, `If-None-Match` for reads and creates,
//! `If-Match` for replace and archive.

use axum::extract::FromRequestParts;
use axum::http::header::{IF_MATCH, IF_NONE_MATCH};
use axum::http::request::Parts;
use axum::http::{HeaderMap, HeaderName, HeaderValue};

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
        let revisions =
            entity_tags("If-Match", &value)?.into_iter().filter_map(revision_of).collect();
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

/// Whether a GET's `If-None-Match` names the current ETag, so the answer is 304; a malformed
/// one is a 400.
pub fn not_modified(headers: &HeaderMap, current_etag: &str) -> Result<bool, ApiError> {
    Ok(IfNoneMatch::read(headers.get(IF_NONE_MATCH))?.names(current_etag))
}

/// A GET's `If-None-Match` alone, checked, for a handler that needs no other header (taking
/// the whole `HeaderMap` copies it).
#[derive(Debug)]
pub struct IfNoneMatch(Option<HeaderValue>);

impl IfNoneMatch {
    fn read(value: Option<&HeaderValue>) -> Result<Self, ApiError> {
        if let Some(value) = value {
            let text = value.to_str().map_err(|_| {
                ApiError::BadRequest(format!("the {IF_NONE_MATCH} header is not readable text"))
            })?;
            if text.trim() != "*" {
                entity_tags("If-None-Match", text)?;
            }
        }
        Ok(Self(value.cloned()))
    }

    /// Whether it names the current ETag, so the answer is 304.
    pub fn names(&self, current_etag: &str) -> bool {
        let Some(value) = self.0.as_ref().and_then(|v| v.to_str().ok()) else {
            return false;
        };
        value.trim() == "*"
            || etag_list(value).any(|tag| tag.strip_prefix("W/").unwrap_or(tag) == current_etag)
    }
}

impl<S: Send + Sync> FromRequestParts<S> for IfNoneMatch {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, _state: &S) -> Result<Self, Self::Rejection> {
        Self::read(parts.headers.get(IF_NONE_MATCH))
    }
}

fn etag_list(value: &str) -> impl Iterator<Item = &str> {
    value.split(',').map(str::trim).filter(|tag| !tag.is_empty())
}

/// The entity tags of a list (RFC 9110 §8.8.3: `"r3"` or `W/"r3"`); one without its double
/// quotes is a 400 that shows it quoted, since a client sending `r3` means `"r3"` and would
/// otherwise be told, wrongly, that someone changed the tag.
fn entity_tags<'a>(name: &str, value: &'a str) -> Result<Vec<&'a str>, ApiError> {
    let tags: Vec<&str> = etag_list(value).collect();
    if tags.is_empty() {
        return Err(ApiError::BadRequest(format!(
            "the {name} header is empty; send an ETag in double quotes, such as {name}: \"r1\""
        )));
    }
    for tag in &tags {
        let opaque = tag.strip_prefix("W/").unwrap_or(tag);
        let quoted = opaque.len() >= 2
            && opaque.starts_with('"')
            && opaque.ends_with('"')
            && !opaque[1..opaque.len() - 1].contains('"');
        if !quoted {
            let bare = opaque.trim_matches('"');
            return Err(ApiError::BadRequest(format!(
                "the {name} header's {tag} is not an ETag: write it in double quotes, as the \
                 ETag header gives it, such as {name}: \"{bare}\""
            )));
        }
    }
    Ok(tags)
}

fn header_text(headers: &HeaderMap, name: HeaderName) -> Result<Option<String>, ApiError> {
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
        assert!(not_modified(&headers("if-none-match", "\"r1\", W/\"r4\""), "\"r4\"").unwrap());
        assert!(!not_modified(&headers("if-none-match", "\"r1\""), "\"r4\"").unwrap());
        assert!(not_modified(&headers("if-none-match", "*"), "\"r4\"").unwrap());
    }

    fn bad_request(result: Result<impl std::fmt::Debug, ApiError>) -> String {
        match result {
            Err(ApiError::BadRequest(message)) => message,
            other => panic!("expected a 400, got {other:?}"),
        }
    }

    #[test]
    fn an_unquoted_etag_is_a_bad_request_that_shows_it_quoted() {
        let message = bad_request(write_condition(&headers("if-match", "r1")));
        assert!(message.contains("If-Match: \"r1\""), "{message}");
        let message = bad_request(write_condition(&headers("if-match", "\"r1\", r2")));
        assert!(message.contains("\"r2\""), "{message}");
        let message = bad_request(not_modified(&headers("if-none-match", "r4"), "\"r4\""));
        assert!(message.contains("If-None-Match: \"r4\""), "{message}");
        bad_request(write_condition(&headers("if-match", "\"r1")));
        bad_request(write_condition(&headers("if-match", " , ")));
    }
}
