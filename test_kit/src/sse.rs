//! The change feed as a client reads it: Server-Sent Events, one response at a time.

use reqwest::{Response, StatusCode};
use serde_json::Value;

use crate::in_process::TestServer;

/// A Server-Sent Events client reading one response.
#[derive(Debug)]
pub struct SseClient {
    pub response: Response,
    pub buffer: String,
}

/// One event as received.
#[derive(Debug, Clone, PartialEq)]
pub struct SseEvent {
    pub id: i64,
    pub kind: String,
    pub data: Value,
}

impl SseClient {
    pub async fn connect(server: &TestServer, token: &str, last_event_id: Option<i64>) -> Self {
        Self::open(&server.client, &server.url, token, last_event_id).await
    }

    /// The feed of the registry at `url` (any replica).
    pub async fn open(
        client: &reqwest::Client,
        url: &str,
        token: &str,
        last_event_id: Option<i64>,
    ) -> Self {
        let mut request = client.get(format!("{url}/api/v1/events")).bearer_auth(token);
        if let Some(id) = last_event_id {
            request = request.header("last-event-id", id.to_string());
        }
        let response = request.send().await.unwrap();
        assert_eq!(response.status(), StatusCode::OK);
        assert!(
            response.headers()["content-type"].to_str().unwrap().starts_with("text/event-stream")
        );
        Self { response, buffer: String::new() }
    }

    /// The next event (skipping heartbeats), or `None` if none arrives within `wait`.
    pub async fn next(&mut self, wait: std::time::Duration) -> Option<SseEvent> {
        let deadline = tokio::time::Instant::now() + wait;
        loop {
            if let Some(end) = self.buffer.find("\n\n") {
                let block: String = self.buffer.drain(..end + 2).collect();
                let (mut id, mut kind, mut data) = (None, String::new(), String::new());
                for line in block.lines() {
                    if let Some(v) = line.strip_prefix("id:") {
                        id = v.trim().parse().ok();
                    } else if let Some(v) = line.strip_prefix("event:") {
                        kind = v.trim().to_owned();
                    } else if let Some(v) = line.strip_prefix("data:") {
                        data.push_str(v.trim());
                    }
                }
                if let Some(id) = id {
                    return Some(SseEvent { id, kind, data: serde_json::from_str(&data).unwrap() });
                }
                continue;
            }
            let chunk =
                tokio::time::timeout_at(deadline, self.response.chunk()).await.ok()?.unwrap()?;
            self.buffer.push_str(&String::from_utf8_lossy(&chunk));
        }
    }

    /// Events until one of `kind` about `key` = `value` arrives.
    pub async fn until(&mut self, kind: &str, key: &str, value: &str) -> SseEvent {
        loop {
            let event =
                self.next(std::time::Duration::from_secs(10)).await.expect("the event arrived");
            if event.kind == kind && event.data[key] == value {
                return event;
            }
        }
    }
}
