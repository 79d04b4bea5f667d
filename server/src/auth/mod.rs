//! Authentication and authorisation: bearer tokens and browser sessions turned into a
//! [`Principal`], and the role rules of DESIGN §4.
//!
//! Nothing here writes to the database on a successful check: the hot path stays read-only.

mod cache;
pub mod login_throttle;
pub mod password;
mod principal;
mod role;
pub mod secret;
pub mod session;
mod user_name;

use axum::http::HeaderMap;
use axum::http::header::AUTHORIZATION;
pub use cache::{RECHECK_AFTER as TOKEN_RECHECK_AFTER, TokenCache};
pub use principal::Principal;
pub use role::Role;
pub use user_name::UserName;

use crate::error::ApiError;
use crate::state::AppState;
use crate::store;

/// Checks the request's credential.
pub async fn authenticate(state: &AppState, headers: &HeaderMap) -> Result<Principal, ApiError> {
    let Some(value) = headers.get(AUTHORIZATION) else {
        // A browser authenticates with its session cookie; unsafe methods are additionally
        // checked for forgery by `http::csrf` before any handler runs.
        if let Some(session_secret) = session::cookie_secret(headers) {
            return session::authenticate(state, &session_secret).await;
        }
        return Err(ApiError::Unauthorized(
            "this needs a credential: send `Authorization: Bearer <token>` (an admin makes \
             tokens with `pps-server token create`), or log in at /"
                .into(),
        ));
    };
    let token = value
        .to_str()
        .ok()
        .and_then(|v| v.strip_prefix("Bearer ").or_else(|| v.strip_prefix("bearer ")))
        .map(str::trim)
        .ok_or_else(|| {
            ApiError::Unauthorized("the Authorization header must be `Bearer <token>`".into())
        })?;
    if !secret::looks_like_token(token) {
        return Err(invalid_token());
    }
    let hash = secret::hash(token);
    let now = time::OffsetDateTime::now_utc().unix_timestamp();
    if let Some(principal) = state.tokens.get(&hash, now) {
        return Ok(principal);
    }
    let record =
        store::tokens::find_live(state.db.reader(), &hash).await?.ok_or_else(invalid_token)?;
    let role = Role::parse(&record.role).ok_or_else(|| {
        anyhow::anyhow!("token {} has an unknown role {:?}", record.id, record.role)
    })?;
    let principal = Principal { role, name: record.name, robot: record.robot_id };
    let expires_at =
        record.expires_at.as_deref().and_then(crate::clock::parse).map(|at| at.unix_timestamp());
    state.tokens.insert(hash, principal.clone(), expires_at);
    Ok(principal)
}

fn invalid_token() -> ApiError {
    ApiError::Unauthorized(
        "this token is not valid: it is unknown, revoked or expired; ask an admin for a new one"
            .into(),
    )
}
