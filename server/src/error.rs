//! The one error type of the HTTP API, rendered as RFC 9457 `application/problem+json`.
//!
//! Every failure a client can see goes through [`ApiError`]; the cause of a 5xx is logged here
//! and never sent to the client.

use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use pps_schema::FieldError;
use serde::Serialize;

/// What went wrong, in the terms a client can act on.
#[derive(Debug, thiserror::Error)]
pub enum ApiError {
    #[error("{0}")]
    BadRequest(String),
    #[error("{0}")]
    Unauthorized(String),
    #[error("{0}")]
    Forbidden(String),
    #[error("{0}")]
    NotFound(String),
    #[error("{0}")]
    MethodNotAllowed(String),
    #[error("{0}")]
    Conflict(String),
    #[error("{0}")]
    PreconditionFailed(String),
    /// The body did not arrive in time; the connection is closed after the answer.
    #[error("{0}")]
    RequestTimeout(String),
    #[error("{0}")]
    PayloadTooLarge(String),
    #[error("{0}")]
    UnsupportedMediaType(String),
    #[error("the request is not valid: {} problem(s)", .0.len())]
    Invalid(Vec<FieldError>),
    #[error("{0}")]
    PreconditionRequired(String),
    #[error("{0}")]
    TooManyRequests(String),
    /// Try again later: the answer carries `Retry-After`.
    #[error("{0}")]
    Unavailable(String),
    #[error(transparent)]
    Internal(anyhow::Error),
}

impl ApiError {
    pub fn status_code(&self) -> StatusCode {
        match self {
            Self::BadRequest(_) => StatusCode::BAD_REQUEST,
            Self::Unauthorized(_) => StatusCode::UNAUTHORIZED,
            Self::Forbidden(_) => StatusCode::FORBIDDEN,
            Self::NotFound(_) => StatusCode::NOT_FOUND,
            Self::MethodNotAllowed(_) => StatusCode::METHOD_NOT_ALLOWED,
            Self::Conflict(_) => StatusCode::CONFLICT,
            Self::PreconditionFailed(_) => StatusCode::PRECONDITION_FAILED,
            Self::RequestTimeout(_) => StatusCode::REQUEST_TIMEOUT,
            Self::PayloadTooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            Self::UnsupportedMediaType(_) => StatusCode::UNSUPPORTED_MEDIA_TYPE,
            Self::Invalid(_) => StatusCode::UNPROCESSABLE_ENTITY,
            Self::PreconditionRequired(_) => StatusCode::PRECONDITION_REQUIRED,
            Self::TooManyRequests(_) => StatusCode::TOO_MANY_REQUESTS,
            Self::Unavailable(_) => StatusCode::SERVICE_UNAVAILABLE,
            Self::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }

    /// A single validation error at one JSON pointer.
    pub fn invalid_at(pointer: &str, message: impl Into<String>) -> Self {
        Self::Invalid(vec![FieldError { pointer: pointer.to_owned(), message: message.into() }])
    }

    fn problem_type(&self) -> &'static str {
        match self {
            Self::Invalid(_) => "validation-error",
            Self::BadRequest(_) => "bad-request",
            Self::Unauthorized(_) => "unauthorized",
            Self::Forbidden(_) => "forbidden",
            Self::NotFound(_) => "not-found",
            Self::MethodNotAllowed(_) => "method-not-allowed",
            Self::Conflict(_) => "conflict",
            Self::PreconditionFailed(_) => "precondition-failed",
            Self::PreconditionRequired(_) => "precondition-required",
            Self::RequestTimeout(_) => "request-timeout",
            Self::PayloadTooLarge(_) => "payload-too-large",
            Self::UnsupportedMediaType(_) => "unsupported-media-type",
            Self::TooManyRequests(_) => "too-many-requests",
            Self::Unavailable(_) => "unavailable",
            Self::Internal(_) => "internal-error",
        }
    }
}

/// Every error: what went wrong, in words a person can act on; a validation error lists every
/// problem in `errors`. The problem document of RFC 9457 with our one extension, `errors`.
#[derive(Debug, Serialize, schemars::JsonSchema)]
#[schemars(rename = "problem", title = "Problem (RFC 9457)")]
pub struct Problem<'a> {
    #[serde(rename = "type")]
    #[schemars(extend("format" = "uri"))]
    pub kind: String,
    pub title: &'a str,
    #[schemars(range(min = 400, max = 599))]
    pub status: u16,
    #[schemars(length(min = 1))]
    pub detail: String,
    #[serde(skip_serializing_if = "<[FieldError]>::is_empty")]
    pub errors: &'a [FieldError],
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let status = self.status_code();
        let detail = match &self {
            Self::Internal(cause) => {
                tracing::error!(error = ?cause, "request failed");
                "the registry hit an internal error; the request changed nothing. Try again, \
                 and tell the administrator if it keeps happening"
                    .to_owned()
            }
            Self::Invalid(errors) => invalid_summary(errors),
            other => other.to_string(),
        };
        let errors = match &self {
            Self::Invalid(errors) => errors.as_slice(),
            _ => &[],
        };
        let problem = Problem {
            kind: format!("https://pps-tags.org/problems/{}", self.problem_type()),
            title: status.canonical_reason().unwrap_or("Error"),
            status: status.as_u16(),
            detail,
            errors,
        };
        let mut response = (status, problem_json(&problem)).into_response();
        let headers = response.headers_mut();
        headers.insert(header::CONTENT_TYPE, HeaderValue::from_static("application/problem+json"));
        if status == StatusCode::UNAUTHORIZED {
            headers.insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        }
        if status == StatusCode::REQUEST_TIMEOUT {
            headers.insert(header::CONNECTION, HeaderValue::from_static("close"));
        }
        if status == StatusCode::SERVICE_UNAVAILABLE {
            headers.insert(header::RETRY_AFTER, HeaderValue::from(RETRY_AFTER_SECONDS));
        }
        response
    }
}

fn problem_json(problem: &Problem<'_>) -> String {
    serde_json::to_string(problem).unwrap_or_else(|_| String::from("{}"))
}

fn invalid_summary(errors: &[FieldError]) -> String {
    match errors {
        [one] if one.pointer.is_empty() => one.message.clone(),
        [one] => format!("{}: {}", one.pointer, one.message),
        many => format!(
            "{} problems; each is listed in `errors` with the JSON pointer of the field it concerns",
            many.len()
        ),
    }
}

/// How long a client is told to wait after a 503: long enough for a lock holder to finish or
/// an operator to free some disk, short enough that a robot's outbox does not idle for long.
pub const RETRY_AFTER_SECONDS: u32 = 5;

impl From<sqlx::Error> for ApiError {
    fn from(error: sqlx::Error) -> Self {
        Self::unwritable(&error).unwrap_or_else(|| Self::Internal(error.into()))
    }
}

impl From<anyhow::Error> for ApiError {
    /// Internal, unless the cause is one to retry after: a busy password hasher, or a database
    /// that cannot take writes just now.
    fn from(error: anyhow::Error) -> Self {
        if let Some(busy) = error.downcast_ref::<crate::identity::password::HashingBusy>() {
            return Self::Unavailable(busy.to_string());
        }
        if let Some(unwritable) = error.downcast_ref::<sqlx::Error>().and_then(Self::unwritable) {
            return unwritable;
        }
        Self::Internal(error)
    }
}

impl ApiError {
    /// The 503 for a database error that means "retry later" (full disk, lock held elsewhere,
    /// no free connection), logged for the operator; `None` for any other error.
    pub fn unwritable(error: &sqlx::Error) -> Option<Self> {
        let reason = crate::store::db::Unwritable::of(error)?;
        reason.log(error);
        Some(Self::Unavailable(reason.advice().into()))
    }
}

/// True when a database error is a violated unique or primary-key constraint: the one place
/// that decides how "it already exists" is recognised.
pub fn is_unique_violation(error: &sqlx::Error) -> bool {
    matches!(error, sqlx::Error::Database(db) if db.is_unique_violation())
}
