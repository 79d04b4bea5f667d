//! A JSON body read straight into a request type, with a problem+json answer naming the field
//! that does not fit.

use axum::extract::{FromRequest, Request};
use serde::de::DeserializeOwned;

use crate::error::ApiError;
use crate::http::extract::JsonBody;

/// A JSON body (media type, size and syntax checked by [`JsonBody`]) deserialised into `T`.
#[derive(Debug)]
pub struct TypedJson<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for TypedJson<T> {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, Self::Rejection> {
        let JsonBody(value) = JsonBody::from_request(req, state).await?;
        serde_json::from_value(value)
            .map(Self)
            .map_err(|error| ApiError::BadRequest(format!("the body does not fit: {error}")))
    }
}
