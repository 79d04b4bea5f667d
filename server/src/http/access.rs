//! Who may call a route, declared where the route is registered and checked before its handler.

use axum::extract::{Request, State};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::auth::{self, Role};
use crate::error::ApiError;
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

/// Authenticates and authorises a request for a route with the given access.
pub async fn check(
    State((state, access)): State<(AppState, Access)>,
    mut request: Request,
    next: Next,
) -> Response {
    if access == Access::Open {
        return next.run(request).await;
    }
    let principal = match auth::authenticate(&state, request.headers()).await {
        Ok(principal) => principal,
        Err(error) => return error.into_response(),
    };
    if !access.admits(principal.role) {
        let needed = match access {
            Access::Admin => "an admin",
            Access::Robot => "a robot",
            _ => "a caretaker or admin",
        };
        return ApiError::Forbidden(format!(
            "this needs {needed} credential; yours has the role {}",
            principal.role
        ))
        .into_response();
    }
    if let Some(robot) = &principal.robot {
        state.presence.saw(robot);
    }
    request.extensions_mut().insert(principal);
    next.run(request).await
}
