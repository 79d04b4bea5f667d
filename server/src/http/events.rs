//! `GET /api/v1/events`: the change feed as Server-Sent Events.
//!
//! Event ids are the stored events' ids: a client that reconnects with `Last-Event-ID` first
//! gets what it missed from the database, then live events, each exactly once, also across a
//! server restart. Without `Last-Event-ID` it starts with the next change.

use std::convert::Infallible;
use std::time::Duration;

use axum::extract::State;
use axum::http::HeaderMap;
use axum::http::header::AUTHORIZATION;
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use futures_util::Stream;
use tokio::sync::{broadcast, mpsc};

use crate::auth::{self, Principal};
use crate::error::ApiError;
use crate::feed::FeedPlace;
use crate::http::extract::Caller;
use crate::http::openapi::doc::{Doc, Param, Reply};
use crate::state::AppState;
use crate::store::events::{self, Event, EventKind};

/// A comment line this often keeps idle connections (and proxies) from timing out.
const HEARTBEAT: Duration = Duration::from_secs(15);
/// How often an open stream checks that its credential still holds: a revoked token, a
/// logout or a deleted user ends the stream within this (plus the token cache's recheck).
const CREDENTIAL_RECHECK: Duration = Duration::from_secs(2);

pub const STREAM: Doc = Doc::new("streamEvents", "The change feed, as Server-Sent Events")
    .describe(
        "Each event names the thing that changed (epc, trial id, robot id). Without \
         Last-Event-ID the stream starts with the next change. A robot sees tag events and its \
         own trials.",
    )
    .params(&[Param::header(
        "Last-Event-ID",
        "The id of the last event received: the stream resumes right after it",
    )])
    .replies(&[
        Reply::event_stream("The stream; a comment line every 15 s keeps it open"),
        Reply::problem(503, "The feed serves as many clients as it can; retry later"),
    ]);

pub async fn stream(
    State(state): State<AppState>,
    Caller(caller): Caller,
    headers: HeaderMap,
) -> Result<Sse<impl Stream<Item = Result<SseEvent, Infallible>>>, ApiError> {
    let holder = holder(&caller, &headers);
    let permit = state.feed.join(&holder).map_err(|full| {
        ApiError::Unavailable(match full {
            crate::feed::Full::Feed => format!(
                "the change feed already serves {} clients; retry in a minute",
                crate::feed::MAX_CLIENTS
            ),
            crate::feed::Full::Credential => format!(
                "{holder} already holds {} change-feed streams, its share, over all its \
                 logins and tokens; close one (a tab, another login) and retry",
                crate::feed::MAX_CLIENTS_PER_CREDENTIAL
            ),
        })
    })?;
    let resume = match headers.get("last-event-id").map(|v| v.to_str().map(str::trim)) {
        Some(Ok(text)) => Some(text.parse::<i64>().map_err(|_| {
            ApiError::BadRequest(format!(
                "Last-Event-ID must be an event id from this feed, not {text:?}"
            ))
        })?),
        Some(Err(_)) => {
            return Err(ApiError::BadRequest("Last-Event-ID is not readable text".into()));
        }
        None => None,
    };
    // Subscribe before reading the backlog, so nothing committed in between is missed.
    let live = state.feed.subscribe();
    let start = match resume {
        Some(id) => id,
        None => events::last_id(state.db.reader()).await?,
    };
    let (sender, receiver) = mpsc::channel(64);
    let credential = Credential(headers);
    tokio::spawn(forward(state, caller, credential, start, live, sender, permit));
    let stream = futures_util::stream::unfold(receiver, |mut receiver| async move {
        receiver.recv().await.map(|event| (Ok(event), receiver))
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::new().interval(HEARTBEAT)))
}

/// The request headers holding the stream's credential (bearer token or session cookie).
struct Credential(HeaderMap);

/// Whom a stream is counted against for the per-holder share: the robot a robot token is
/// bound to, the user a browser session belongs to, or the name of a person's API token. So
/// logging in again, or minting another token for the same robot, gives no more streams.
fn holder(caller: &Principal, headers: &HeaderMap) -> String {
    match &caller.robot {
        Some(robot) => format!("robot {robot}"),
        None if headers.contains_key(AUTHORIZATION) => format!("the token {:?}", caller.name),
        None => format!("user {}", caller.name),
    }
}

/// Sends the backlog after `cursor`, then live events, until the client goes away or its
/// credential stops being valid.
async fn forward(
    state: AppState,
    caller: std::sync::Arc<Principal>,
    credential: Credential,
    mut cursor: i64,
    mut live: broadcast::Receiver<std::sync::Arc<Event>>,
    sender: mpsc::Sender<SseEvent>,
    _permit: FeedPlace,
) {
    if catch_up(&state, &caller, &mut cursor, &sender).await.is_err() {
        return;
    }
    let mut recheck = tokio::time::interval(CREDENTIAL_RECHECK);
    recheck.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        let received = tokio::select! {
            () = sender.closed() => return,
            () = state.feed.closed() => return,
            _ = recheck.tick() => {
                let checked =
                    auth::authenticate(&state.tokens, &state.db, &state.clock, &credential.0).await;
                match checked {
                    Err(ApiError::Unauthorized(_)) => return,
                    // Keep serving while the check itself cannot be made (a busy database).
                    Ok(_) | Err(_) => continue,
                }
            }
            received = live.recv() => received,
        };
        let sent = match received {
            Ok(event) if event.id <= cursor => Ok(()),
            Ok(event) => {
                cursor = event.id;
                send(&caller, &event, &sender).await
            }
            // Too slow for the live buffer: read what was missed from the database.
            Err(broadcast::error::RecvError::Lagged(_)) => {
                catch_up(&state, &caller, &mut cursor, &sender).await
            }
            Err(broadcast::error::RecvError::Closed) => return,
        };
        if sent.is_err() {
            return;
        }
    }
}

async fn catch_up(
    state: &AppState,
    caller: &Principal,
    cursor: &mut i64,
    sender: &mpsc::Sender<SseEvent>,
) -> Result<(), ()> {
    loop {
        let batch = events::after(state.db.reader(), *cursor, 500).await.map_err(|error| {
            tracing::warn!(%error, "cannot read the change feed for a client");
        })?;
        let done = batch.len() < 500;
        for event in batch {
            *cursor = event.id;
            send(caller, &event, sender).await?;
        }
        if done {
            return Ok(());
        }
    }
}

async fn send(
    caller: &Principal,
    event: &Event,
    sender: &mpsc::Sender<SseEvent>,
) -> Result<(), ()> {
    if !visible_to(caller, event) {
        return Ok(());
    }
    let sse = SseEvent::default()
        .id(event.id.to_string())
        .event(event.kind.as_str())
        .data(event.data.to_string());
    sender.send(sse).await.map_err(|_| ())
}

/// A robot sees tag events and its own trials; people see everything.
fn visible_to(caller: &Principal, event: &Event) -> bool {
    let Some(robot) = &caller.robot else { return true };
    match event.kind {
        kind if kind.is_tag_event() => true,
        EventKind::TrialRecorded | EventKind::TrialUpdated => {
            event.data.get("robot").and_then(|r| r.as_str()) == Some(robot.as_str())
        }
        _ => false,
    }
}
