//! The live change feed: events committed to the database, fanned out to SSE clients.
//!
//! One pump reads new event rows and broadcasts them. Writers in this process wake it right
//! after they commit; it also polls, so changes made by another process (the CLI importing
//! tags) reach clients and invalidate caches too.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::{Notify, OwnedSemaphorePermit, Semaphore, broadcast, watch};

use crate::store::db::Db;
use crate::store::events::{self, Event};

/// How often the pump looks for events written by other processes.
const POLL_EVERY: Duration = Duration::from_millis(500);
/// Live events buffered per client before it counts as lagging (and catches up from the DB).
const LIVE_BUFFER: usize = 4096;
/// SSE clients served at once; each holds a connection and a task.
pub const MAX_CLIENTS: usize = 256;
/// Streams one holder (a robot, a user over all their sessions, a person's token) may hold at
/// once: a robot needs one, a caretaker one per open tab; a quarter of the feed leaves room
/// for everyone else when one holder runs away.
pub const MAX_CLIENTS_PER_CREDENTIAL: usize = MAX_CLIENTS / 4;

/// Why a client found no place on the feed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Full {
    /// Every place is taken.
    Feed,
    /// Its holder (robot, user or token) holds its share already.
    Credential,
}

/// A client's place on the feed, given back when dropped.
#[derive(Debug)]
pub struct FeedPlace {
    _place: OwnedSemaphorePermit,
    holders: Arc<Mutex<HashMap<String, usize>>>,
    credential: String,
}

impl Drop for FeedPlace {
    fn drop(&mut self) {
        let mut holders = self.holders.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(count) = holders.get_mut(&self.credential) {
            *count -= 1;
            if *count == 0 {
                holders.remove(&self.credential);
            }
        }
    }
}

#[derive(Debug)]
pub struct ChangeFeed {
    live: broadcast::Sender<Arc<Event>>,
    wake: Notify,
    clients: Arc<Semaphore>,
    /// Places held per holder: a robot, a user, a person's token.
    holders: Arc<Mutex<HashMap<String, usize>>>,
    closing: watch::Sender<bool>,
}

impl Default for ChangeFeed {
    fn default() -> Self {
        Self {
            live: broadcast::channel(LIVE_BUFFER).0,
            wake: Notify::new(),
            clients: Arc::new(Semaphore::new(MAX_CLIENTS)),
            holders: Arc::default(),
            closing: watch::Sender::new(false),
        }
    }
}

impl ChangeFeed {
    /// A place for one more SSE client of `credential` (its holder), held until it leaves.
    pub fn join(&self, credential: &str) -> Result<FeedPlace, Full> {
        let mut holders = self.holders.lock().unwrap_or_else(|e| e.into_inner());
        let held = holders.get(credential).copied().unwrap_or(0);
        if held >= MAX_CLIENTS_PER_CREDENTIAL {
            return Err(Full::Credential);
        }
        let place = self.clients.clone().try_acquire_owned().map_err(|_| Full::Feed)?;
        holders.insert(credential.to_owned(), held + 1);
        Ok(FeedPlace {
            _place: place,
            holders: self.holders.clone(),
            credential: credential.to_owned(),
        })
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
