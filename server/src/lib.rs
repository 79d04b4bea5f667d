//! The PPS-tag registry: tag entries keyed by EPC, the robots' trials, per-robot overrides,
//! learned values and a change feed, over HTTP/JSON.
//!
//! The binary is a thin shell: everything is here, so tests run the real router in-process.

pub mod accept;
pub mod auth;
pub mod background;
pub mod backup;
pub mod cli;
pub mod clock;
pub mod colour_learning;
pub mod counted_purposes;
pub mod db;
pub mod effective;
pub mod effective_cache;

pub mod error;
pub mod export;
pub mod feed;
pub mod home_assistant;
pub mod http;
pub mod identity;
pub mod learning;
pub mod metrics;
pub mod picture;
pub mod presence;
pub mod private_file;
pub mod retention;
pub mod seed;
pub mod sightings;
pub mod state;
pub mod store;
pub mod task_board;
pub mod telemetry;
pub mod transport;
pub mod trial_filter;
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
    serve_with(listener, state, ServeOptions::default(), shutdown).await
}

/// What `serve_with` does beyond plain [`serve`].
#[derive(Debug, Clone, Default)]
pub struct ServeOptions {
    /// Connection limits and TLS.
    pub transport: transport::Transport,
    /// Thin the force samples of trials received longer ago than this, once a day.
    pub thin_forces_after: Option<retention::Age>,
    /// Show the tags in Home Assistant through this MQTT broker.
    pub home_assistant: Option<home_assistant::Config>,
}

/// [`serve`] with connection limits, TLS and retention as `options` say.
pub async fn serve_with(
    listener: TcpListener,
    state: AppState,
    options: ServeOptions,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    background::start(&state).await.map_err(std::io::Error::other)?;
    retention::start_daily_pictures(state.db.clone(), state.clock.clone(), state.pictures_per_tag);
    if let Some(age) = options.thin_forces_after {
        retention::start_daily(state.db.clone(), state.clock.clone(), age);
    }
    let bridge = options.home_assistant.clone().map(|config| home_assistant::start(&state, config));
    let feed = state.feed.clone();
    let shutdown = async move {
        shutdown.await;
        // Change-feed streams never end by themselves; end them so the drain can finish.
        feed.close();
    };
    transport::serve(listener, router(state.clone()), &options.transport, shutdown).await?;
    background::flush(&state).await;
    if let Some(bridge) = bridge {
        // Its devices marked unavailable before the process goes.
        let _ = tokio::time::timeout(home_assistant::GOODBYE_WITHIN, bridge).await;
    }
    Ok(())
}
