//! `/api/v1/tokens`: API tokens for robots and scripts, managed by admins. A token's secret is
//! shown once, in the answer that creates it.

use axum::Json;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde::Deserialize;

use crate::answers::accounts::{MintedTokenAnswer, RevokedToken, RoleName, TokenAnswer};
use crate::error::ApiError;
use crate::http::extract::JsonBody;
use crate::http::openapi::doc::{Body, Doc, Param, ParamType, Reply};
use crate::http::page::Page;
use crate::identity::Role;
use crate::state::AppState;
use crate::store::tokens;

pub const LIST: Doc = Doc::new("listTokens", "Every API token, without secrets")
    .replies(&[Reply::page("All tokens (one page)", "token_record")]);

pub async fn list(State(state): State<AppState>) -> Result<Json<Page<TokenAnswer>>, ApiError> {
    let items = tokens::list(state.db.reader()).await?;
    Ok(Json(Page { items: items.into_iter().map(TokenAnswer::from).collect(), next_cursor: None }))
}

/// A token to mint: its role, who holds it, and when it stops working.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "new_token")]
pub struct NewToken {
    #[schemars(with = "RoleName")]
    role: Role,
    /// Who holds it; for a robot token, the robot's id.
    name: String,
    /// Days until it stops working; without it the token does not expire.
    #[schemars(extend("exclusiveMinimum" = 0, "maximum" = MAX_DAYS))]
    expires_in_days: Option<f64>,
}

/// The longest a token may live: ten years.
const MAX_DAYS: f64 = 3650.0;

pub const CREATE: Doc = Doc::new("createToken", "Mint an API token; its secret is shown only now")
    .body(Body::json("new_token", "Role, name (a robot token's name is its robot id), expiry"))
    .replies(&[Reply::json(201, "Minted", "minted_token"), Reply::INVALID]);

pub async fn create(
    State(state): State<AppState>,
    JsonBody(body): JsonBody,
) -> Result<Response, ApiError> {
    let request: NewToken = serde_json::from_value(body).map_err(|error| {
        ApiError::invalid_at("", format!("a token needs role (admin, caretaker or robot), name and optionally expires_in_days: {error}"))
    })?;
    let name = request.name.trim();
    if let Some(problem) = tokens::name_problem(request.role, name) {
        return Err(ApiError::invalid_at("/name", problem));
    }
    let expires_at = match request.expires_in_days {
        Some(days) if !(days > 0.0 && days <= MAX_DAYS) => {
            return Err(ApiError::invalid_at(
                "/expires_in_days",
                "expires_in_days is more than 0 and at most 3650",
            ));
        }
        Some(days) => Some(state.clock.now() + time::Duration::seconds_f64(days * 86_400.0)),
        None => None,
    };
    let minted = tokens::create(&state.db, request.role, name, expires_at).await?;
    // The secret is in this answer only: no cache along the way may keep it.
    let no_store = [(axum::http::header::CACHE_CONTROL, "no-store")];
    Ok((StatusCode::CREATED, no_store, Json(MintedTokenAnswer::from(minted))).into_response())
}

pub const REVOKE: Doc = Doc::new("revokeToken", "Revoke a token, at once")
    .params(&[Param::path("id", ParamType::Text, "The token's id (not its secret)")])
    .replies(&[
        Reply::json(200, "Revoked", "revoked_token"),
        Reply::problem(404, "No live token has this id"),
    ]);

pub async fn revoke(
    State(state): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<RevokedToken>, ApiError> {
    if !tokens::revoke(&state.db, &id).await? {
        return Err(ApiError::NotFound(format!("no live token has the id {id:?}")));
    }
    // Revocation through the API bites at once, not after the cache's re-check interval.
    state.tokens.clear();
    Ok(Json(RevokedToken::new(id)))
}
