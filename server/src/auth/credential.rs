//! A request's credential checked: a bearer token or a browser session turned into a
//! [`Principal`], from memory when it can be.

use std::sync::Arc;

use axum::http::HeaderMap;
use axum::http::header::AUTHORIZATION;

use super::cache::TokenCache;
use super::principal::Principal;
use super::session;
use crate::clock::Clock;
use crate::error::ApiError;
use crate::identity::{Role, secret};
use crate::store;
use crate::store::db::Db;

/// Checks the request's credential against the recently confirmed `tokens`, then `db`, at the
/// time `clock` says.
pub async fn authenticate(
    tokens: &TokenCache,
    db: &Db,
    clock: &Clock,
    headers: &HeaderMap,
) -> Result<Arc<Principal>, ApiError> {
    check_in_memory(tokens, clock, headers).finish(tokens, db, clock).await
}

/// How far a credential could be checked without the database.
#[derive(Debug)]
pub enum Check {
    /// Decided: a recently confirmed token, or a credential refused on sight.
    Done(Result<Arc<Principal>, ApiError>),
    /// A well-formed token not confirmed recently, by its digest.
    Token([u8; 32]),
    /// A browser session, by its secret.
    Session(String),
}

impl Check {
    /// Decides, reading the database if memory could not; a token confirmed there joins
    /// `tokens`.
    pub async fn finish(
        self,
        tokens: &TokenCache,
        db: &Db,
        clock: &Clock,
    ) -> Result<Arc<Principal>, ApiError> {
        match self {
            Self::Done(decided) => decided,
            Self::Token(digest) => look_up_token(tokens, db, clock, digest).await,
            Self::Session(secret) => session::authenticate(db, clock, &secret).await.map(Arc::new),
        }
    }
}

/// Checks the credential as far as memory can: on the robots' hot path, all the way.
pub fn check_in_memory(tokens: &TokenCache, clock: &Clock, headers: &HeaderMap) -> Check {
    let Some(value) = headers.get(AUTHORIZATION) else {
        // A browser authenticates with its session cookie; unsafe methods are additionally
        // checked for forgery by `http::csrf` before any handler runs.
        if let Some(session_secret) = session::cookie_secret(headers) {
            return Check::Session(session_secret);
        }
        return Check::Done(Err(ApiError::Unauthorized(
            "this needs a credential: send `Authorization: Bearer <token>` (an admin makes \
             tokens with `pps-server token create`), or log in at /"
                .into(),
        )));
    };
    let token = value
        .to_str()
        .ok()
        .and_then(|v| v.strip_prefix("Bearer ").or_else(|| v.strip_prefix("bearer ")))
        .map(str::trim);
    let Some(token) = token else {
        return Check::Done(Err(ApiError::Unauthorized(
            "the Authorization header must be `Bearer <token>`".into(),
        )));
    };
    if !secret::looks_like_token(token) {
        return Check::Done(Err(invalid_token()));
    }
    let digest = secret::digest(token);
    match tokens.get(&digest, clock.now()) {
        Some(principal) => Check::Done(Ok(principal)),
        None => Check::Token(digest),
    }
}

/// Confirms a token with the database and remembers it for a while.
async fn look_up_token(
    tokens: &TokenCache,
    db: &Db,
    clock: &Clock,
    digest: [u8; 32],
) -> Result<Arc<Principal>, ApiError> {
    let now = clock.now();
    let record = store::tokens::find_live(db.reader(), &hex::encode(digest), now)
        .await?
        .ok_or_else(invalid_token)?;
    let role = Role::parse(&record.role).ok_or_else(|| {
        anyhow::anyhow!("token {} has an unknown role {:?}", record.id, record.role)
    })?;
    // A robot token's name passed as a robot id when it was minted (`tokens::name_problem`).
    let robot = record.robot_id.as_deref().and_then(|id| pps_schema::RobotId::parse(id).ok());
    let principal = Arc::new(Principal { role, name: record.name, robot });
    tokens.insert(digest, principal.clone(), now, record.expires_at);
    Ok(principal)
}

fn invalid_token() -> ApiError {
    ApiError::Unauthorized(
        "this token is not valid: it is unknown, revoked or expired; ask an admin for a new one"
            .into(),
    )
}
