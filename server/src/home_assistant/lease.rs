//! One bridge for the whole registry: of several replicas on one database, the one holding
//! the bridge's lease runs it; the others stand by and take over once it runs out.

use std::time::Duration;

use super::Config;
use super::bridge::{self, Ended};
use crate::ops::bridge_status::Status;
use crate::state::AppState;
use crate::store::db::Db;
use crate::store::home_assistant;

/// A lease lasts this long unless renewed. Longer than the broker takes to notice a dead
/// holder (1.5 keep-alives), so its last will has fired before another replica announces.
pub const LEASE: Duration = Duration::from_secs(20);
/// The holder renews, and the others look, this often.
pub const RENEW_EVERY: Duration = Duration::from_secs(5);

/// This process's claim on the bridge.
#[derive(Debug, Clone)]
pub struct Lease {
    holder: String,
}

impl Lease {
    fn new() -> Self {
        Self { holder: uuid::Uuid::new_v4().to_string() }
    }

    /// Who holds it, as the lease row says.
    pub fn holder(&self) -> &str {
        &self.holder
    }

    /// Takes the lease at `now` or renews it; true while this process holds it.
    pub async fn take(&self, db: &Db, now: time::OffsetDateTime) -> sqlx::Result<bool> {
        let mut tx = db.begin_write().await?;
        let held = home_assistant::take_lease(&mut tx, &self.holder, now, now + LEASE).await?;
        tx.commit().await?;
        Ok(held)
    }

    async fn release(&self, db: &Db) {
        let released = async {
            let mut tx = db.begin_write().await?;
            home_assistant::release_lease(&mut tx, &self.holder).await?;
            tx.commit().await
        };
        if let Err(error) = released.await {
            tracing::warn!(%error, "could not give up the Home Assistant bridge's lease");
        }
    }
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
