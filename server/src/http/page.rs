//! List pages: the `{"items", "next_cursor"}` envelope, `limit` bounds and opaque cursors.
//!
//! A cursor encodes the sort key of the last item returned; the next page starts strictly
//! after it, so concurrent inserts never make a page skip or repeat an item.

use base64::Engine;
use base64::engine::general_purpose::URL_SAFE_NO_PAD;
use serde::Serialize;

use crate::error::ApiError;

pub const DEFAULT_LIMIT: u32 = 50;
pub const MAX_LIMIT: u32 = 500;

/// `limit` and `cursor`, for lists with no filters of their own.
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PageParams {
    pub limit: Option<u32>,
    pub cursor: Option<String>,
}

/// One page of a list; pass next_cursor back as `cursor` for the next.
#[derive(Debug, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "{T}_page")]
pub struct Page<T> {
    pub items: Vec<T>,
    /// `null` on the last page.
    pub next_cursor: Option<String>,
}

impl<T> Page<T> {
    /// The same page with each item turned into what the API answers.
    pub fn map<U>(self, answer: impl FnMut(T) -> U) -> Page<U> {
        Page { items: self.items.into_iter().map(answer).collect(), next_cursor: self.next_cursor }
    }
}

/// Checks a requested page size against the bounds of DESIGN §4.
pub fn limit(requested: Option<u32>) -> Result<u32, ApiError> {
    match requested.unwrap_or(DEFAULT_LIMIT) {
        0 => Err(ApiError::BadRequest("limit must be at least 1".into())),
        n if n > MAX_LIMIT => Err(ApiError::BadRequest(format!(
            "limit must be at most {MAX_LIMIT}; page through longer lists with next_cursor"
        ))),
        n => Ok(n),
    }
}

pub fn encode_cursor(key: &str) -> String {
    URL_SAFE_NO_PAD.encode(key)
}

pub fn decode_cursor(cursor: &str) -> Result<String, ApiError> {
    URL_SAFE_NO_PAD
        .decode(cursor)
        .ok()
        .and_then(|bytes| String::from_utf8(bytes).ok())
        .ok_or_else(not_ours)
}

/// The position a numeric cursor (a revision, a sequence number) names; 0 without one.
pub fn decode_position(cursor: Option<&str>) -> Result<i64, ApiError> {
    match cursor {
        None => Ok(0),
        Some(cursor) => decode_cursor(cursor)?.parse().map_err(|_| not_ours()),
    }
}

fn not_ours() -> ApiError {
    ApiError::BadRequest(
        "this cursor is not one the registry gave out; pass next_cursor back unchanged".into(),
    )
}

/// Builds a page from up to `limit + 1` rows: the extra row only tells that more exist.
pub fn page<T>(mut rows: Vec<T>, limit: u32, key: impl Fn(&T) -> String) -> Page<T> {
    let more = rows.len() > limit as usize;
    rows.truncate(limit as usize);
    let next_cursor = if more { rows.last().map(|last| encode_cursor(&key(last))) } else { None };
    Page { items: rows, next_cursor }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_and_cursors() {
        assert_eq!(limit(None).unwrap(), 50);
        assert_eq!(limit(Some(500)).unwrap(), 500);
        assert!(limit(Some(501)).is_err());
        assert!(limit(Some(0)).is_err());
        assert_eq!(decode_cursor(&encode_cursor("ABC")).unwrap(), "ABC");
        assert!(decode_cursor("%%%").is_err());
        let p = page(vec![1, 2, 3], 2, |n| n.to_string());
        assert_eq!(p.items, vec![1, 2]);
        assert_eq!(decode_cursor(p.next_cursor.as_deref().unwrap()).unwrap(), "2");
        assert!(page(vec![1, 2], 2, |n| n.to_string()).next_cursor.is_none());
    }
}
