//! The live change feed: events committed to the database, fanned out to SSE clients.
//!
//! One pump reads new event rows and broadcasts them. Writers in this process wake it right
//! after they commit; it also polls, so changes made by another process (the CLI importing
//! tags) reach clients and invalidate caches too.

use std::sync::Arc;
use std::time::Duration;

use tokio::sync::{Notify, OwnedSemaphorePermit, Semaphore, broadcast, watch};

use crate::db::Db;
use crate::store::events::{self, Event};

/// How often the pump looks for events written by other processes.
const POLL_EVERY: Duration = Duration::from_millis(500);
/// Live events buffered per client before it counts as lagging (and catches up from the DB).
const LIVE_BUFFER: usize = 4096;
/// SSE clients served at once; each holds a connection and a task.
pub const MAX_CLIENTS: usize = 256;

#[derive(Debug)]
pub struct ChangeFeed {
    live: broadcast::Sender<Arc<Event>>,
    wake: Notify,
    clients: Arc<Semaphore>,
    closing: watch::Sender<bool>,
}

impl Default for ChangeFeed {
    fn default() -> Self {
        Self {
            live: broadcast::channel(LIVE_BUFFER).0,
            wake: Notify::new(),
            clients: Arc::new(Semaphore::new(MAX_CLIENTS)),
            closing: watch::Sender::new(false),
        }
    }
}

impl ChangeFeed {
    /// A place for one more SSE client, held until it leaves; `None` when all are taken.
    pub fn join(&self) -> Option<OwnedSemaphorePermit> {
        self.clients.clone().try_acquire_owned().ok()
    }

    /// Ends every client's stream, so a graceful shutdown does not wait on them forever.
    pub fn close(&self) {
        self.closing.send_replace(true);
    }

    /// Completes when the feed is closing.
    pub async fn closed(&self) {
        let mut closing = self.closing.subscribe();
        let _ = closing.wait_for(|closing| *closing).await;
    }

    /// SSE clients connected now.
    pub fn clients(&self) -> usize {
        MAX_CLIENTS - self.clients.available_permits()
    }

    /// Tells the pump that events were just committed.
    pub fn committed(&self) {
        self.wake.notify_one();
    }

    pub fn subscribe(&self) -> broadcast::Receiver<Arc<Event>> {
        self.live.subscribe()
    }

    /// Broadcasts every event committed after `after`, forever; `seen` runs for each event
    /// first (to invalidate caches), in order.
    pub async fn pump(&self, db: Db, mut after: i64, seen: impl Fn(&Event)) {
        loop {
            let _ = tokio::time::timeout(POLL_EVERY, self.wake.notified()).await;
            loop {
                let batch = match events::after(db.reader(), after, 1000).await {
                    Ok(batch) => batch,
                    Err(error) => {
                        tracing::warn!(%error, "cannot read the change feed; retrying");
                        break;
                    }
                };
                let full = batch.len() == 1000;
                for event in batch {
                    after = event.id;
                    seen(&event);
                    // No subscribers is fine: nobody is listening right now.
                    let _ = self.live.send(Arc::new(event));
                }
                if !full {
                    break;
                }
            }
        }
    }
}
