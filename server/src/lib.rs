//! The PPS-tag registry: tag entries keyed by EPC, the robots' trials, per-robot overrides,
//! learned values and a change feed, over HTTP/JSON.
//!
//! The binary is a thin shell: everything is here, so tests run the real router in-process.

pub mod auth;
pub mod cli;
pub mod clock;
pub mod db;
pub mod entry;
pub mod error;
pub mod http;
pub mod seed;
pub mod state;
pub mod store;
pub mod telemetry;

use std::future::Future;

pub use db::Db;
pub use http::{RouteSpec, router, router_with_routes};
pub use state::AppState;
use tokio::net::TcpListener;

/// Serves the registry on `listener` until `shutdown` completes, then drains open requests.
pub async fn serve(
    listener: TcpListener,
    state: AppState,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    axum::serve(listener, router(state)).with_graceful_shutdown(shutdown).await
}
