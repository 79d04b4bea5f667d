//! `/api/v1/session`: browser login with a password, who is logged in, and logout.

use std::net::SocketAddr;
use std::time::Duration;

use axum::Extension;
use axum::Json;
use axum::body::Body;
use axum::extract::{ConnectInfo, State};
use axum::http::header::{CACHE_CONTROL, RETRY_AFTER, SET_COOKIE};
use axum::http::{HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use serde::Deserialize;

use crate::answers::accounts::{Credential, SessionAnswer};
use crate::auth::{login_throttle, session};
use crate::error::ApiError;
use crate::http::extract::Caller;
use crate::http::typed_json::TypedJson;
use crate::identity::{UserName, password, secret};
use crate::state::AppState;
use crate::store;

/// Where a browser logs in and out.
pub const PATH: &str = "/api/v1/session";

/// The user name and password of a login.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "login")]
pub struct Login {
    username: String,
    password: String,
}

/// `POST /api/v1/session`: checks the password and, when it is right, sets the session cookie.
pub async fn login(
    State(state): State<AppState>,
    client: Option<Extension<ConnectInfo<SocketAddr>>>,
    secure: Option<Extension<crate::transport::SecureTransport>>,
    TypedJson(login): TypedJson<Login>,
) -> Result<Response, ApiError> {
    let name = UserName::parse(&login.username).ok();
    let mut throttle_keys = vec![login_throttle::user_key(&login.username)];
    if let Some(Extension(ConnectInfo(address))) = client {
        throttle_keys.push(login_throttle::address_key(address.ip()));
    }
    // Claimed before anything is looked up or hashed, so parallel guesses wait like serial ones.
    let attempt = match state.login_throttle.begin(throttle_keys, state.clock.now()) {
        Ok(attempt) => attempt,
        Err(wait) => return Ok(too_many_attempts(wait)),
    };
    let found = match &name {
        Some(name) => store::users::find_with_hash(state.db.reader(), name).await?,
        None => None,
    };
    let stored_hash = found.as_ref().map(|(_, hash)| hash.clone());
    // An over-long password is never right; it is checked against the decoy so it costs the same.
    let too_long = login.password.len() > password::MAX_BYTES;
    let candidate = if too_long { String::new() } else { login.password };
    let right = password::verify_off_runtime(candidate, stored_hash).await? && !too_long;
    let (Some(name), Some((user, _)), true) = (name, found, right) else {
        attempt.failed(state.clock.now());
        return Err(ApiError::Unauthorized("wrong user name or password".into()));
    };
    attempt.succeeded();

    let session_secret = session::mint_secret();
    let now = state.clock.now();
    let expires_at = now + session::LIFETIME;
    store::sessions::create(&state.db, &secret::hash(&session_secret), &name, now, expires_at)
        .await?;
    let body = SessionAnswer {
        name: user.name,
        role: user.role,
        credential: Credential::Session {
            expires_at,
            csrf_token: session::csrf_token(&session_secret),
        },
    };
    let mut response = no_store(Json(body).into_response());
    response
        .headers_mut()
        .insert(SET_COOKIE, session::set_cookie(&session_secret, secure.is_some()));
    Ok(response)
}

/// `GET /api/v1/session`: who the credential belongs to, and for a browser session its
/// anti-forgery token and expiry (what the UI needs after a reload).
pub async fn current(
    State(state): State<AppState>,
    Caller(caller): Caller,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    let body = match session::browser_secret(&headers) {
        Some(session_secret) => {
            let hash = secret::hash(&session_secret);
            let live = store::sessions::find_live(state.db.reader(), &hash, state.clock.now())
                .await?
                .ok_or_else(|| {
                    ApiError::Unauthorized("your session has ended; log in again".into())
                })?;
            Credential::Session {
                expires_at: live.expires_at,
                csrf_token: session::csrf_token(&session_secret),
            }
        }
        None => Credential::Token { robot: caller.robot.clone() },
    };
    let body = SessionAnswer {
        name: caller.name.clone(),
        role: caller.role.as_str().to_owned(),
        credential: body,
    };
    Ok(no_store(Json(body).into_response()))
}

/// `DELETE /api/v1/session`: ends this browser session and clears its cookie.
pub async fn logout(
    State(state): State<AppState>,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    let Some(session_secret) = session::browser_secret(&headers) else {
        return Err(ApiError::BadRequest(
            "logout ends a browser session, and this request has none; an API token is \
             revoked with DELETE /api/v1/tokens/{id} instead"
                .into(),
        ));
    };
    store::sessions::delete(&state.db, &secret::hash(&session_secret)).await?;
    let mut response = no_store(StatusCode::NO_CONTENT.into_response());
    response.headers_mut().insert(SET_COOKIE, session::clear_cookie());
    Ok(response)
}

/// The answer while a login name or address must wait after wrong passwords: 429 with
/// `Retry-After`, without the password being looked at.
pub(super) fn too_many_attempts(wait: Duration) -> Response {
    let seconds = wait.as_secs() + u64::from(wait.subsec_nanos() > 0);
    let mut response = ApiError::TooManyRequests(format!(
        "too many wrong passwords, or another attempt for this name or address is being \
         checked; wait {seconds} s before trying again"
    ))
    .into_response();
    response.headers_mut().insert(RETRY_AFTER, HeaderValue::from(seconds));
    response
}

/// Answers about credentials are never cached, by the browser or anything in between.
fn no_store(mut response: Response<Body>) -> Response<Body> {
    response.headers_mut().insert(CACHE_CONTROL, HeaderValue::from_static("no-store"));
    response
}
