//! The PPS-tag registry: tag entries keyed by EPC, the robots' trials, per-robot overrides,
//! learned values and a change feed, over HTTP/JSON.
//!
//! The binary is a thin shell: everything is here, so tests run the real router in-process.

pub mod auth;
pub mod background;
pub mod cli;
pub mod clock;
pub mod db;
pub mod effective;
pub mod effective_cache;
pub mod entry;
pub mod error;
pub mod feed;
pub mod http;
pub mod learning;
pub mod metrics;
pub mod presence;
pub mod seed;
pub mod sightings;
pub mod state;
pub mod store;
pub mod telemetry;
pub mod trial_writer;

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
    background::start(&state).await.map_err(std::io::Error::other)?;
    let feed = state.feed.clone();
    let shutdown = async move {
        shutdown.await;
        feed.close();
    };
    axum::serve(listener, router(state.clone())).with_graceful_shutdown(shutdown).await?;
    background::flush(&state).await;
    Ok(())
}
