//! The ids in URLs, parsed at the boundary: a path segment or a query parameter becomes the
//! type it names (an [`Epc`], a [`RobotId`], a trial's or a task's UUID, a user name) before a
//! handler sees it, and a bad one is answered with what was expected.

use axum::extract::{FromRequestParts, RawPathParams};
use axum::http::request::Parts;
use pps_schema::{Epc, RobotId};
use uuid::Uuid;

use crate::error::ApiError;
use crate::identity::UserName;

/// What one path segment (or query parameter) can name.
pub trait Segment: Sized {
    /// Parses the (percent-decoded) text, or says in a sentence what it should have been.
    fn parse_segment(raw: &str) -> Result<Self, ApiError>;
}

/// A trial's id, as its URLs carry it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TrialId(pub Uuid);

/// A task's id, as its URLs carry it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TaskId(pub Uuid);

impl Segment for Epc {
    fn parse_segment(raw: &str) -> Result<Self, ApiError> {
        Epc::parse(raw)
            .map_err(|error| ApiError::BadRequest(format!("{raw:?} is not an EPC: {error}")))
    }
}

impl Segment for RobotId {
    fn parse_segment(raw: &str) -> Result<Self, ApiError> {
        RobotId::parse(raw)
            .map_err(|error| ApiError::BadRequest(format!("{raw:?} is not a robot id: {error}")))
    }
}

impl Segment for TrialId {
    fn parse_segment(raw: &str) -> Result<Self, ApiError> {
        parse_uuid(raw, "a trial id").map(Self)
    }
}

impl Segment for TaskId {
    fn parse_segment(raw: &str) -> Result<Self, ApiError> {
        parse_uuid(raw, "a task id").map(Self)
    }
}

impl Segment for UserName {
    fn parse_segment(raw: &str) -> Result<Self, ApiError> {
        UserName::parse(raw)
            .map_err(|error| ApiError::BadRequest(format!("{raw:?} is not a user name: {error}")))
    }
}

fn parse_uuid(raw: &str, what: &str) -> Result<Uuid, ApiError> {
    Uuid::parse_str(raw)
        .map_err(|error| ApiError::BadRequest(format!("{raw:?} is not {what} (a UUID): {error}")))
}

/// The route's path segments, parsed: `InPath<Epc>` for `/tags/{epc}`, `InPath<(RobotId, Epc)>`
/// for `/robots/{robot}/tags/{epc}`. Reads the router's raw captures (no deserializer between),
/// so the robots' hot path pays only for the parse itself.
#[derive(Debug)]
pub struct InPath<T>(pub T);

/// Segments taken in the route's order.
pub trait FromSegments: Sized {
    fn from_segments(segments: &[&str]) -> Result<Self, ApiError>;
}

impl<T: Segment> FromSegments for T {
    fn from_segments(segments: &[&str]) -> Result<Self, ApiError> {
        match segments {
            [one] => T::parse_segment(one),
            _ => Err(route_mismatch(1, segments.len())),
        }
    }
}

impl<A: Segment, B: Segment> FromSegments for (A, B) {
    fn from_segments(segments: &[&str]) -> Result<Self, ApiError> {
        match segments {
            [a, b] => Ok((A::parse_segment(a)?, B::parse_segment(b)?)),
            _ => Err(route_mismatch(2, segments.len())),
        }
    }
}

/// A handler asking for more or fewer segments than its route has is our bug, not the client's.
fn route_mismatch(wanted: usize, found: usize) -> ApiError {
    ApiError::Internal(anyhow::anyhow!("handler wants {wanted} path segments; route has {found}"))
}

impl<S: Send + Sync, T: FromSegments> FromRequestParts<S> for InPath<T> {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &S) -> Result<Self, Self::Rejection> {
        let raw = RawPathParams::from_request_parts(parts, state)
            .await
            .map_err(|rejection| ApiError::BadRequest(rejection.body_text()))?;
        let mut segments = [""; 2];
        let mut count = 0;
        for (_, value) in raw.iter() {
            if count == segments.len() {
                return Err(route_mismatch(segments.len(), count + 1));
            }
            segments[count] = value;
            count += 1;
        }
        T::from_segments(&segments[..count]).map(Self)
    }
}
