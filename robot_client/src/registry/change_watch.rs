//! Follows the registry's change feed (SSE) and invalidates cached entries of tags that
//! change, so a robot can use its cache without asking while the feed is live.
//!
//! A feed that drops is followed again, after the waits of [`super::retry`]; one that refuses the
//! credential (401, 403) is not, since asking again cannot help: the watch stops and says why.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use reqwest::StatusCode;
use serde_json::Value;
use tokio::task::JoinHandle;

use super::entry_cache::EntryCache;

/// The running watch; stops when dropped.
#[derive(Debug)]
pub struct ChangeWatch {
    task: JoinHandle<()>,
    refusal: Arc<Mutex<Option<String>>>,
}

/// How one connection to the feed ended.
enum Ended {
    /// Dropped, unreachable or answered with passing trouble: follow it again. `was_live` says
    /// whether it was streaming before it dropped.
    Dropped { was_live: bool },
    /// The registry refused the credential: following again cannot help.
    Refused(String),
}

impl Drop for ChangeWatch {
    fn drop(&mut self) {
        self.task.abort();
    }
}

impl ChangeWatch {
    pub(crate) fn start(
        http: reqwest::Client,
        base: String,
        token: String,
        cache: Arc<EntryCache>,
        live: Arc<AtomicBool>,
    ) -> Self {
        let refusal = Arc::new(Mutex::new(None));
        let refused = refusal.clone();
        let task = tokio::spawn(async move {
            let mut last_event_id: Option<String> = None;
            let mut waits = super::retry::waits();
            loop {
                let ended = follow(&http, &base, &token, &cache, &live, &mut last_event_id).await;
                // The feed dropped: until it is back, every entry must be revalidated.
                live.store(false, Ordering::Release);
                cache.invalidate_all();
                match ended {
                    Ended::Refused(why) => {
                        *refused.lock().unwrap_or_else(|e| e.into_inner()) = Some(why);
                        return;
                    }
                    // It was live: a drop now is news, so the next try comes soon.
                    Ended::Dropped { was_live: true } => waits = super::retry::waits(),
                    Ended::Dropped { was_live: false } => {}
                }
                let wait = waits.next().unwrap_or(super::retry::LONGEST_WAIT);
                #[allow(
                    clippy::disallowed_methods,
                    reason = "back-off between attempts to reach the feed"
                )]
                tokio::time::sleep(wait).await;
            }
        });
        Self { task, refusal }
    }

    /// Why the watch stopped for good (the registry refused the robot's credential), if it did;
    /// the cache then revalidates every entry it serves.
    pub fn refused(&self) -> Option<String> {
        self.refusal.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// Whether the watch has stopped for good: it follows the feed no more.
    pub fn stopped(&self) -> bool {
        self.task.is_finished()
    }
}

/// Reads one connection's worth of events.
async fn follow(
    http: &reqwest::Client,
    base: &str,
    token: &str,
    cache: &EntryCache,
    live: &AtomicBool,
    last_event_id: &mut Option<String>,
) -> Ended {
    let mut request = http
        .get(format!("{base}/api/v1/events"))
        .bearer_auth(token)
        .timeout(Duration::from_secs(24 * 3600));
    if let Some(id) = last_event_id.as_deref() {
        request = request.header("last-event-id", id);
    }
    let Ok(mut response) = request.send().await else { return Ended::Dropped { was_live: false } };
    let status = response.status();
    if status == StatusCode::UNAUTHORIZED || status == StatusCode::FORBIDDEN {
        let detail = super::RegistryError::from_response(response).await;
        return Ended::Refused(format!(
            "the change feed refused this robot's credential ({detail}); entries are revalidated \
             on every read until the robot restarts with a valid token"
        ));
    }
    if !status.is_success() {
        return Ended::Dropped { was_live: false };
    }
    // Anything cached before the feed was live may have changed unannounced.
    cache.invalidate_all();
    live.store(true, Ordering::Release);
    // Bytes until a whole event is in: a character split across chunks is decoded whole.
    let mut buffer: Vec<u8> = Vec::new();
    while let Ok(Some(chunk)) = response.chunk().await {
        buffer.extend_from_slice(&chunk);
        while let Some(end) = buffer.windows(2).position(|pair| pair == b"\n\n") {
            let block: Vec<u8> = buffer.drain(..end + 2).collect();
            let Ok(block) = std::str::from_utf8(&block) else { continue };
            let mut data = String::new();
            for line in block.lines() {
                if let Some(id) = line.strip_prefix("id:") {
                    *last_event_id = Some(id.trim().to_owned());
                } else if let Some(value) = line.strip_prefix("data:") {
                    data.push_str(value.trim());
                }
            }
            if let Ok(event) = serde_json::from_str::<Value>(&data) {
                for key in ["epc", "new_epc"] {
                    if let Some(epc) = event.get(key).and_then(Value::as_str) {
                        cache.invalidate(epc);
                    }
                }
            }
        }
    }
    Ended::Dropped { was_live: true }
}
