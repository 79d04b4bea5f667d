//! `/api/v1/users`: the logins of the web UI, managed by admins; and password changes, one's
//! own with the current password or anyone's as an admin.

use axum::Json;
use axum::extract::State;
use axum::http::header::LOCATION;
use axum::http::{HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use pps_schema::FieldError;
use schemars::{JsonSchema, json_schema};
use serde::Deserialize;

use crate::answers::accounts::UserAnswer;
use crate::answers::accounts::UserRole;
use crate::answers::written_schema;
use crate::auth::{login_throttle, session};
use crate::error::{ApiError, is_unique_violation};
use crate::http::extract::{ApiQuery, Caller};
use crate::http::ids::InPath;
use crate::http::page::{self, Page};
use crate::http::session::too_many_attempts;
use crate::http::typed_json::TypedJson;
use crate::identity::{Role, UserName, password, secret, user_name};
use crate::state::AppState;
use crate::store;
use crate::store::users;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ListParams {
    limit: Option<u32>,
    cursor: Option<String>,
}

/// `GET /api/v1/users`: every login, without password hashes.
pub async fn list(
    State(state): State<AppState>,
    ApiQuery(params): ApiQuery<ListParams>,
) -> Result<Json<Page<UserAnswer>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = params.cursor.as_deref().map(page::decode_cursor).transpose()?;
    let rows = users::list(state.db.reader(), after.as_deref(), limit + 1).await?;
    Ok(Json(page::page(rows, limit, |user| user.name.clone()).map(|user| UserAnswer::from(&user))))
}

/// A new login: name, role (caretaker or admin) and password.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "new_user")]
pub struct NewUser {
    #[schemars(with = "UserNameText")]
    name: String,
    #[schemars(with = "UserRole")]
    role: String,
    #[schemars(with = "PasswordText")]
    password: String,
}

written_schema!(
    /// A user name as [`UserName::parse`] takes it.
    UserNameText,
    "user_name",
    inline: false,
    json_schema!({
        "description": "Letters, digits, '.', '_' and '-', starting with a letter or digit; \
            stored lower-case",
        "type": "string",
        "pattern": format!("^[A-Za-z0-9][A-Za-z0-9._-]{{0,{}}}$", user_name::MAX_CHARS - 1)
    })
);

written_schema!(
    /// A password as [`password::problem`] takes it.
    PasswordText,
    "password",
    inline: false,
    json_schema!({
        "description": format!(
            "At least {} characters, at most {} bytes, not only spaces",
            password::MIN_CHARS,
            password::MAX_BYTES
        ),
        "type": "string",
        "minLength": password::MIN_CHARS,
        "maxLength": password::MAX_BYTES
    })
);

/// `POST /api/v1/users`: makes a login; 409 when the name is taken.
pub async fn create(
    State(state): State<AppState>,
    TypedJson(new): TypedJson<NewUser>,
) -> Result<Response, ApiError> {
    let mut errors = Vec::new();
    let name = UserName::parse(&new.name)
        .map_err(|message| errors.push(FieldError { pointer: "/name".into(), message }))
        .ok();
    let role = match Role::parse(&new.role) {
        Some(role @ (Role::Admin | Role::Caretaker)) => Some(role),
        _ => {
            errors.push(FieldError {
                pointer: "/role".into(),
                message: format!(
                    "a user is a \"caretaker\" or an \"admin\", not {:?} (robots use tokens)",
                    new.role
                ),
            });
            None
        }
    };
    if let Some(message) = password::problem(&new.password) {
        errors.push(FieldError { pointer: "/password".into(), message });
    }
    let (Some(name), Some(role), true) = (name, role, errors.is_empty()) else {
        return Err(ApiError::Invalid(errors));
    };
    let hash = password::hash_off_runtime(new.password).await?;
    let record = users::create(&state.db, &name, role, &hash).await.map_err(|error| {
        if is_unique_violation(&error) {
            ApiError::Conflict(format!("there is already a user named {name}"))
        } else {
            error.into()
        }
    })?;
    let mut response = (StatusCode::CREATED, Json(UserAnswer::from(&record))).into_response();
    if let Ok(location) = HeaderValue::from_str(&format!("/api/v1/users/{name}")) {
        response.headers_mut().insert(LOCATION, location);
    }
    Ok(response)
}

/// `DELETE /api/v1/users/{name}`: removes a login and ends its sessions.
pub async fn delete(
    State(state): State<AppState>,
    InPath(name): InPath<UserName>,
) -> Result<StatusCode, ApiError> {
    if users::delete(&state.db, &name).await? {
        Ok(StatusCode::NO_CONTENT)
    } else {
        Err(no_such_user(&name))
    }
}

/// The new password, and the current one unless an admin changes it.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "password_change")]
pub struct PasswordChange {
    #[schemars(with = "PasswordText")]
    password: String,
    /// Needed unless an admin changes it.
    current_password: Option<String>,
}

/// `PUT /api/v1/users/{name}/password`: one's own password with the current one, or anyone's as
/// an admin. The user's other sessions end; the session that made the change stays.
pub async fn set_password(
    State(state): State<AppState>,
    Caller(caller): Caller,
    InPath(name): InPath<UserName>,
    headers: HeaderMap,
    TypedJson(change): TypedJson<PasswordChange>,
) -> Result<Response, ApiError> {
    let own = caller.name == name.as_str() && caller.role != Role::Robot;
    if caller.role != Role::Admin && !own {
        return Err(ApiError::Forbidden(format!(
            "you may change only your own password; {name}'s needs an admin"
        )));
    }
    if let Some(message) = password::problem(&change.password) {
        return Err(ApiError::invalid_at("/password", message));
    }
    let (_, stored) = users::find_with_hash(state.db.reader(), &name)
        .await?
        .ok_or_else(|| no_such_user(&name))?;
    // An admin needs no current password; anyone else proves who they are with it.
    if caller.role != Role::Admin
        && let Err(refusal) =
            check_current_password(&state, &name, change.current_password, stored).await
    {
        return Ok(refusal);
    }
    let hash = password::hash_off_runtime(change.password).await?;
    if !users::set_password(&state.db, &name, &hash).await? {
        return Err(no_such_user(&name));
    }
    let keep = session::browser_secret(&headers).map(|s| secret::hash(&s));
    store::sessions::delete_for_user(&state.db, &name, keep.as_deref()).await?;
    Ok(StatusCode::NO_CONTENT.into_response())
}

/// A non-admin proves they are the user by the current password, slowed down like a login.
async fn check_current_password(
    state: &AppState,
    name: &UserName,
    current: Option<String>,
    stored: String,
) -> Result<(), Response> {
    let Some(current) = current else {
        return Err(ApiError::invalid_at(
            "/current_password",
            "give your current password to set a new one",
        )
        .into_response());
    };
    let attempt = state
        .login_throttle
        .begin(vec![login_throttle::user_key(name.as_str())], state.clock.now())
        .map_err(too_many_attempts)?;
    let right = password::verify_off_runtime(current, Some(stored))
        .await
        .map_err(|error| ApiError::from(error).into_response())?;
    if right {
        attempt.succeeded();
        Ok(())
    } else {
        attempt.failed(state.clock.now());
        Err(ApiError::invalid_at("/current_password", "this is not your current password")
            .into_response())
    }
}

fn no_such_user(name: &UserName) -> ApiError {
    ApiError::NotFound(format!("there is no user named {name}; GET /api/v1/users lists them"))
}
