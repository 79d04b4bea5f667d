//! Browser sessions: an HttpOnly, SameSite=Strict cookie holding a random 256-bit secret, of
//! which the database keeps only the SHA-256, and the anti-forgery token derived from it.
//!
//! Expiry is fixed at login ([`LIFETIME`]) and never slides, so checking a session writes
//! nothing to the database. The cookie never authenticates a request that carries an
//! `Authorization` header: bearer tokens keep their own path.

use axum::http::header::{AUTHORIZATION, COOKIE};
use axum::http::{HeaderMap, HeaderValue};
use base64::Engine;
use base64::engine::general_purpose::URL_SAFE_NO_PAD;
use sha2::{Digest, Sha256};

use super::principal::Principal;
use crate::clock::Clock;
use crate::error::ApiError;
use crate::identity::{Role, secret};
use crate::store;
use crate::store::db::Db;

/// The session cookie's name.
pub const COOKIE_NAME: &str = "pps_session";

/// The header a browser sends the anti-forgery token in on every unsafe request.
pub const CSRF_HEADER: &str = "x-csrf-token";

/// How long a session lasts after login: a working day, then the caretaker logs in again.
pub const LIFETIME: time::Duration = time::Duration::hours(12);

/// A new session secret: 256 random bits, URL-safe.
pub fn mint_secret() -> String {
    URL_SAFE_NO_PAD.encode(secret::random_bytes::<32>())
}

/// The anti-forgery token of a session: derived from its secret, so it needs no storage and
/// dies with the session, yet reveals nothing about the secret. Only same-origin script can
/// read it (from the login answer or `GET /api/v1/session`), and it must come back in
/// [`CSRF_HEADER`], which a cross-site form or link cannot set.
pub fn csrf_token(session_secret: &str) -> String {
    let digest = Sha256::new_with_prefix(b"pps csrf token\0").chain_update(session_secret);
    URL_SAFE_NO_PAD.encode(digest.finalize())
}

/// Whether `presented` is the anti-forgery token of the session, compared in constant time.
pub fn csrf_matches(session_secret: &str, presented: &str) -> bool {
    let expected = csrf_token(session_secret);
    expected.len() == presented.len()
        && expected.bytes().zip(presented.bytes()).fold(0u8, |acc, (a, b)| acc | (a ^ b)) == 0
}

/// The session secret in the request's `Cookie` header, if there is one.
pub fn cookie_secret(headers: &HeaderMap) -> Option<String> {
    headers
        .get_all(COOKIE)
        .iter()
        .filter_map(|value| value.to_str().ok())
        .flat_map(|value| value.split(';'))
        .filter_map(|pair| pair.trim().split_once('='))
        .find(|(name, _)| *name == COOKIE_NAME)
        .map(|(_, value)| value.trim().to_owned())
        .filter(|value| !value.is_empty())
}

/// The session secret of a request that a browser session authenticates: the cookie counts
/// only when no `Authorization` header is present.
pub fn browser_secret(headers: &HeaderMap) -> Option<String> {
    cookie_secret(headers).filter(|_| !headers.contains_key(AUTHORIZATION))
}

/// The `Set-Cookie` value that gives the browser a session; `secure` over HTTPS, so the
/// browser never sends it in clear text.
pub fn set_cookie(session_secret: &str, secure: bool) -> HeaderValue {
    let value = format!(
        "{COOKIE_NAME}={session_secret}; Path=/; Max-Age={}; HttpOnly; SameSite=Strict{}",
        LIFETIME.whole_seconds(),
        if secure { "; Secure" } else { "" }
    );
    HeaderValue::from_str(&value).expect("a session secret is URL-safe text")
}

/// The `Set-Cookie` value that makes the browser forget its session.
pub fn clear_cookie() -> HeaderValue {
    HeaderValue::from_static("pps_session=; Path=/; Max-Age=0; HttpOnly; SameSite=Strict")
}

/// The user of a live session in `db`, at the time `clock` says.
pub async fn authenticate(
    db: &Db,
    clock: &Clock,
    session_secret: &str,
) -> Result<Principal, ApiError> {
    let hash = secret::hash(session_secret);
    let user =
        store::sessions::find_live(db.reader(), &hash, clock.now()).await?.ok_or_else(|| {
            ApiError::Unauthorized(
                "your session has ended (it expired or you logged out); log in again".into(),
            )
        })?;
    let role = Role::parse(&user.role)
        .ok_or_else(|| anyhow::anyhow!("user {} has an unknown role {:?}", user.name, user.role))?;
    Ok(Principal { role, name: user.name, robot: None })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_session_among_other_cookies() {
        let mut headers = HeaderMap::new();
        headers.append(COOKIE, "theme=dark; pps_session=abc_-1".parse().unwrap());
        assert_eq!(cookie_secret(&headers).as_deref(), Some("abc_-1"));
        let mut other = HeaderMap::new();
        other.append(COOKIE, "xpps_session=abc; pps_session=".parse().unwrap());
        assert_eq!(cookie_secret(&other), None);
    }

    #[test]
    fn csrf_tokens_are_bound_to_their_session() {
        let (a, b) = (mint_secret(), mint_secret());
        assert_ne!(a, b);
        assert!(csrf_matches(&a, &csrf_token(&a)));
        assert!(!csrf_matches(&a, &csrf_token(&b)));
        assert!(!csrf_matches(&a, ""));
        assert_ne!(csrf_token(&a), a);
    }

    #[test]
    fn cookie_flags() {
        let cookie = set_cookie("s3cret", false).to_str().unwrap().to_owned();
        assert!(cookie.starts_with("pps_session=s3cret;"));
        for flag in ["HttpOnly", "SameSite=Strict", "Path=/", "Max-Age=43200"] {
            assert!(cookie.contains(flag), "{cookie} lacks {flag}");
        }
        assert!(!cookie.contains("Secure"), "plain HTTP on the LAN could not send it back");
        assert!(set_cookie("s3cret", true).to_str().unwrap().ends_with("; Secure"));
    }
}
