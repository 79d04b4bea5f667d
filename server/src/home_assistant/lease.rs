//! The bridge's lease: this process's claim on running the bridge, taken and renewed in the
//! database, and given up when the server stops.

use std::time::Duration;

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
    pub(super) fn new() -> Self {
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

    pub(super) async fn release(&self, db: &Db) {
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
