//! Answers for requests no route takes: unknown paths (404) and methods a route lacks (405),
//! both as problem+json like every other error.

use axum::extract::Request;
use axum::http::StatusCode;
use axum::http::header::CONTENT_TYPE;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;

pub async fn not_found(request: Request) -> ApiError {
    ApiError::NotFound(format!(
        "there is nothing at {}; the API lives under /api/v1 (see /api/v1/openapi.json)",
        request.uri().path()
    ))
}

/// Turns axum's empty 405 into a problem document.
pub async fn method_not_allowed(request: Request, next: Next) -> Response {
    let method = request.method().clone();
    let path = request.uri().path().to_owned();
    let response = next.run(request).await;
    if response.status() != StatusCode::METHOD_NOT_ALLOWED
        || response.headers().contains_key(CONTENT_TYPE)
    {
        return response;
    }
    // axum adds the `Allow` header after this layer has run, to our response as to its own.
    ApiError::MethodNotAllowed(format!(
        "{path} does not accept {method}; the Allow header lists the methods it does"
    ))
    .into_response()
}
