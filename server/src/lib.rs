//! The PPS-tag registry: tag entries keyed by EPC, the robots' trials, per-robot overrides,
//! learned values and a change feed, over HTTP/JSON.
//!
//! The binary is a thin shell: everything is here, so tests run the real router in-process.
//!
//! By what they are for:
//! - [`http`] answers requests and [`auth`] says who asks; [`transport`] holds the
//!   connections; [`error`] is the one error they answer with.
//! - [`store`] is the only SQL, on the database it opens; [`identity`] are the people,
//!   passwords and secrets below it, and [`trials`] the values it takes about trials (a list's
//!   filter, the purposes a rate counts, a picture).
//! - [`tags`], [`learning`], [`robots`] and the [`trial_history`] (trials written, aged out,
//!   exported) are the registry's domain between the store and HTTP; [`accept`] takes a
//!   client's document in. [`effective_entry`] (a tag as one robot should use it) and
//!   [`tasks`] (a task asked for) work on the whole [`state`], for the routes and the Home
//!   Assistant bridge alike.
//! - [`feed`] fans out changes, [`background`] does what the hot path only noted, [`clock`]
//!   says what time it is and how times are written.
//! - [`home_assistant`] is the smart-home bridge; [`ops`] and [`cli`] are the operator's side,
//!   and every file written for the operator is a [`private_file`].

pub mod accept;
pub mod answers;
pub mod auth;
pub mod background;
pub mod cli;
pub mod clock;
pub mod effective_entry;
pub mod error;
pub mod feed;
pub mod home_assistant;
pub mod http;
pub mod identity;
pub mod learning;
pub mod ops;
pub mod private_file;
pub mod robots;
pub mod state;
pub mod store;
pub mod tags;
pub mod tasks;
pub mod transport;
pub mod trial_history;
pub mod trials;

use std::future::Future;

pub use http::{RouteSpec, router, router_with_routes};
pub use state::AppState;
pub use store::db::Db;
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
    pub thin_forces_after: Option<trial_history::retention::Age>,
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
    trial_history::retention::start_daily_pictures(
        state.db.clone(),
        state.clock.clone(),
        state.pictures_per_tag,
    );
    if let Some(age) = options.thin_forces_after {
        trial_history::retention::start_daily(state.db.clone(), state.clock.clone(), age);
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
