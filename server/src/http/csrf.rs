//! Cross-site request forgery: an unsafe request authenticated by the session cookie must
//! carry the session's anti-forgery token in `X-CSRF-Token`.
//!
//! The cookie is already SameSite=Strict; this is the second lock, for browsers or set-ups where
//! SameSite does not hold. A cross-site page can make the browser send the cookie, but it can
//! neither read the token nor set a custom header without a CORS preflight, which the registry
//! never grants. Bearer-token requests carry no cookie credential and pass untouched. Login
//! itself is exempt (it is authenticated by the password in a JSON body, which a cross-site form
//! cannot send either), so a stale cookie never blocks logging in again.

use axum::extract::Request;
use axum::http::Method;

use crate::auth::session::{self, CSRF_HEADER};
use crate::error::ApiError;
use crate::http::session::PATH as LOGIN_PATH;

/// The refusal of a cookie-authenticated unsafe request without the session's anti-forgery
/// token; `None` lets the request through.
pub fn refusal(request: &Request) -> Option<ApiError> {
    let method = request.method();
    let safe = matches!(*method, Method::GET | Method::HEAD | Method::OPTIONS);
    if safe {
        return None;
    }
    let is_login = *method == Method::POST && request.uri().path() == LOGIN_PATH;
    let headers = request.headers();
    let session_secret = session::browser_secret(headers).filter(|_| !is_login)?;
    let presented = headers.get(CSRF_HEADER).and_then(|value| value.to_str().ok());
    if presented.is_some_and(|token| session::csrf_matches(&session_secret, token)) {
        return None;
    }
    Some(ApiError::Forbidden(format!(
        "this request came with the session cookie but without its anti-forgery token; send \
         the `csrf_token` from GET {LOGIN_PATH} in the {CSRF_HEADER} header"
    )))
}
