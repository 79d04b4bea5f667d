//! Follows the registry's change feed (SSE) and invalidates cached entries of tags that
//! change, so a robot can use its cache without asking while the feed is live.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use serde_json::Value;
use tokio::task::JoinHandle;

use super::entry_cache::EntryCache;

/// The running watch; stops when dropped.
#[derive(Debug)]
pub struct ChangeWatch {
    task: JoinHandle<()>,
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
        let task = tokio::spawn(async move {
            let mut last_event_id: Option<String> = None;
            loop {
                follow(&http, &base, &token, &cache, &live, &mut last_event_id).await;
                // The feed dropped: until it is back, every entry must be revalidated.
                live.store(false, Ordering::Release);
                cache.invalidate_all();
                tokio::time::sleep(Duration::from_secs(2)).await;
            }
        });
        Self { task }
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
) {
    let mut request = http
        .get(format!("{base}/api/v1/events"))
        .bearer_auth(token)
        .timeout(Duration::from_secs(24 * 3600));
    if let Some(id) = last_event_id.as_deref() {
        request = request.header("last-event-id", id);
    }
    let Ok(mut response) = request.send().await else { return };
    if !response.status().is_success() {
        return;
    }
    // Anything cached before the feed was live may have changed unannounced.
    cache.invalidate_all();
    live.store(true, Ordering::Release);
    let mut buffer = String::new();
    while let Ok(Some(chunk)) = response.chunk().await {
        buffer.push_str(&String::from_utf8_lossy(&chunk));
        while let Some(end) = buffer.find("\n\n") {
            let block: String = buffer.drain(..end + 2).collect();
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
}
