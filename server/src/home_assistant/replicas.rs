//! One bridge for the whole registry: of several replicas on one database, the one holding
//! the bridge's lease runs it; the others stand by and take over once it runs out.

use super::Config;
use super::bridge::{self, Ended};
use super::lease::{Lease, RENEW_EVERY};
use crate::ops::bridge_status::Status;
use crate::state::AppState;

/// Starts the bridge; it runs until the feed closes (the server is shutting down), and the
/// handle completes once it said goodbye to the broker.
pub fn start(state: &AppState, config: Config) -> tokio::task::JoinHandle<()> {
    state.home_assistant.configured(config.broker.to_string(), config.prefix.clone());
    state.home_assistant.set(Status::Standby);
    tokio::spawn(run(state.clone(), config))
}

/// Runs the bridge whenever this process holds the lease, until the server stops.
pub async fn run(state: AppState, config: Config) {
    let lease = Lease::new();
    let mut standing_by = false;
    loop {
        match lease.take(&state.db, state.clock.now()).await {
            Ok(true) => {
                standing_by = false;
                tracing::info!(broker = %config.broker, "running the Home Assistant bridge");
                match bridge::run(&state, &config, &lease).await {
                    Ended::LeaseLost => {
                        tracing::warn!("another replica took the Home Assistant bridge over");
                        continue;
                    }
                    Ended::Shutdown => {
                        lease.release(&state.db).await;
                        return;
                    }
                    Ended::Unable => {}
                }
            }
            Ok(false) => {
                if !standing_by {
                    tracing::info!("another replica runs the Home Assistant bridge; standing by");
                    standing_by = true;
                }
                state.home_assistant.set(Status::Standby);
            }
            Err(error) => tracing::warn!(%error, "cannot take the Home Assistant bridge's lease"),
        }
        #[allow(clippy::disallowed_methods, reason = "the lease is renewed on a period")]
        let renew = tokio::time::sleep(RENEW_EVERY);
        tokio::select! {
            () = renew => {}
            () = state.feed.closed() => return,
        }
    }
}
