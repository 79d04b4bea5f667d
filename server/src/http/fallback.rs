//! Answers for requests no route takes: unknown paths (404) and methods a route lacks (405),
//! both as problem+json like every other error.

use axum::extract::Request;
use axum::http::Method;

use crate::error::ApiError;

pub async fn not_found(request: Request) -> ApiError {
    ApiError::NotFound(format!(
        "there is nothing at {}; the API lives under /api/v1 (see /api/v1/openapi.json)",
        request.uri().path()
    ))
}

/// The problem document for a method a route lacks (axum's own 405 is empty).
pub fn method_not_allowed(method: &Method, path: &str) -> ApiError {
    ApiError::MethodNotAllowed(format!(
        "{path} does not accept {method}; the Allow header lists the methods it does"
    ))
}
