//! Who may call a route, declared where the route is registered and checked before its handler.

use std::convert::Infallible;
use std::sync::Arc;
use std::task::{Context, Poll};

use axum::extract::Request;
use axum::response::{IntoResponse, Response};
use futures_util::future::{BoxFuture, Either};
use tower::{Layer, Service};

use crate::auth::{self, Check, Principal};
use crate::error::ApiError;
use crate::identity::Role;
use crate::state::AppState;

/// The roles of DESIGN §4's table, as far as they can be decided from the route alone.
/// "That robot" rules, which depend on the path or the record, are checked by the handler.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// No credential needed.
    Open,
    /// Any valid credential.
    Anyone,
    /// Caretakers and admins.
    Editors,
    /// Admins only.
    Admin,
    /// A robot (for its own records, checked by the handler), caretakers and admins.
    RobotOrEditors,
    /// Robots only (acting as themselves, checked by the handler).
    Robot,
}

impl Access {
    /// Which roles get past the route's own check.
    pub fn admits(self, role: Role) -> bool {
        match self {
            Self::Open | Self::Anyone | Self::RobotOrEditors => true,
            Self::Editors => matches!(role, Role::Caretaker | Role::Admin),
            Self::Admin => role == Role::Admin,
            Self::Robot => role == Role::Robot,
        }
    }
}

/// The access check of one route, as a layer: given to `route_layer` where the route is
/// registered, so it runs after routing and before the handler.
#[derive(Debug, Clone)]
pub struct Gate {
    state: AppState,
    access: Access,
}

impl Gate {
    pub fn new(state: AppState, access: Access) -> Self {
        Self { state, access }
    }
}

impl<S> Layer<S> for Gate {
    type Service = Gated<S>;

    fn layer(&self, inner: S) -> Self::Service {
        Gated { inner, state: self.state.clone(), access: self.access }
    }
}

#[derive(Debug, Clone)]
pub struct Gated<S> {
    inner: S,
    state: AppState,
    access: Access,
}

impl<S> Service<Request> for Gated<S>
where
    S: Service<Request, Response = Response, Error = Infallible> + Clone + Send + 'static,
    S::Future: Send + 'static,
{
    type Response = Response;
    type Error = Infallible;
    /// The route's own future when memory decides (the hot path allocates nothing here);
    /// a boxed one when the database must be asked first.
    type Future = Either<S::Future, BoxFuture<'static, Result<Response, Infallible>>>;

    fn poll_ready(&mut self, cx: &mut Context<'_>) -> Poll<Result<(), Self::Error>> {
        self.inner.poll_ready(cx)
    }

    fn call(&mut self, mut request: Request) -> Self::Future {
        if self.access == Access::Open {
            return Either::Left(self.inner.call(request));
        }
        let checked =
            auth::check_in_memory(&self.state.tokens, &self.state.clock, request.headers());
        let pending = match checked {
            Check::Done(decided) => {
                return match admit(&self.state, self.access, decided, &mut request) {
                    Ok(()) => Either::Left(self.inner.call(request)),
                    Err(refusal) => {
                        Either::Right(Box::pin(std::future::ready(Ok(refusal.into_response()))))
                    }
                };
            }
            pending => pending,
        };
        // The ready service goes into the future; a fresh clone waits for the next request.
        let clone = self.inner.clone();
        let mut inner = std::mem::replace(&mut self.inner, clone);
        let (state, access) = (self.state.clone(), self.access);
        Either::Right(Box::pin(async move {
            let decided = pending.finish(&state.tokens, &state.db, &state.clock).await;
            match admit(&state, access, decided, &mut request) {
                Ok(()) => inner.call(request).await,
                Err(refusal) => Ok(refusal.into_response()),
            }
        }))
    }
}

/// Lets an authenticated caller through if the route admits its role, noting a robot as seen
/// and leaving the principal for the handler.
fn admit(
    state: &AppState,
    access: Access,
    authenticated: Result<Arc<Principal>, ApiError>,
    request: &mut Request,
) -> Result<(), ApiError> {
    let principal = authenticated?;
    if !access.admits(principal.role) {
        let needed = match access {
            Access::Admin => "an admin",
            Access::Robot => "a robot",
            _ => "a caretaker or admin",
        };
        return Err(ApiError::Forbidden(format!(
            "this needs {needed} credential; yours has the role {}",
            principal.role
        )));
    }
    if let Some(robot) = &principal.robot {
        state.presence.saw(robot.as_str(), state.clock.now());
    }
    request.extensions_mut().insert(principal);
    Ok(())
}
