//! The registry's background work: fanning out the change feed, flushing what the hot path
//! only noted in memory (robots' last-seen times, unknown EPCs for the inbox), expiring tasks
//! and returning the tasks of robots whose lease ran out to the queue. Robots waiting for a
//! task are woken here, from the feed, for every change that could give them one.

use std::time::Duration;

use pps_schema::TaskState;
use serde_json::Value;

use crate::state::AppState;
use crate::store::events::{self, Event, EventKind};
use crate::store::{inbox, robots, tasks};

/// Unknown EPCs reach the inbox within this (DESIGN §4: "within a second").
const SIGHTINGS_EVERY: Duration = Duration::from_millis(400);
const PRESENCE_EVERY: Duration = Duration::from_secs(5);
/// Old events are dropped this often (they are cheap to keep for a minute).
const PRUNE_EVERY: Duration = Duration::from_secs(60);

/// Starts the background tasks; they run until the runtime stops.
pub async fn start(state: &AppState) -> anyhow::Result<()> {
    state.presence.load(robots::presence(state.db.reader()).await?);
    let after = events::last_id(state.db.reader()).await?;

    let pump = state.clone();
    tokio::spawn(async move {
        let feed = pump.feed.clone();
        feed.pump(pump.db.clone(), after, |event| invalidate(&pump, event)).await;
    });

    let flusher = state.clone();
    tokio::spawn(async move {
        let mut sightings = tokio::time::interval(SIGHTINGS_EVERY);
        let mut presence = tokio::time::interval(PRESENCE_EVERY);
        let mut prune = tokio::time::interval(PRUNE_EVERY);
        let mut leases = tokio::time::interval(flusher.tasks.sweep_every());
        // A test that moves the clock past a lease need not wait for the next sweep.
        let mut clock_moves = flusher.clock.moves();
        loop {
            tokio::select! {
                _ = sightings.tick() => flush_sightings(&flusher).await,
                _ = presence.tick() => flush_presence(&flusher).await,
                _ = prune.tick() => prune_events(&flusher).await,
                _ = leases.tick() => expire_leases(&flusher).await,
                () = clock_moves.next() => expire_leases(&flusher).await,
            }
        }
    });
    Ok(())
}

/// Flushes what is still only in memory (at shutdown).
pub async fn flush(state: &AppState) {
    flush_sightings(state).await;
    flush_presence(state).await;
}

/// Keeps caches right when the change came from another process (the CLI, another replica)
/// as well, and wakes robots waiting here for a task another replica queued.
fn invalidate(state: &AppState, event: &Event) {
    let epc = |key: &str| event.data.get(key).and_then(Value::as_str).map(str::to_owned);
    match event.kind {
        // A household's learned colour is in every entry of its robot class.
        EventKind::LearnedChanged if event.data.get("household") == Some(&Value::Bool(true)) => {
            state.effective.clear()
        }
        EventKind::TagChanged
        | EventKind::TagArchived
        | EventKind::TagRetagged
        | EventKind::LearnedChanged => {
            for epc in [epc("epc"), epc("new_epc")].into_iter().flatten() {
                state.effective.forget_tag(&epc);
            }
        }
        EventKind::RobotChanged => state.effective.clear(),
        _ => {}
    }
    if could_change_an_offer(event) {
        state.tasks.changed();
    }
}

/// Whether a robot waiting for a task could get another answer after this event: a task asked
/// for or back in the queue (here or on another replica), or a change to what a robot can do
/// (a tag, a robot, learned values) or to who ranks first for it (reliability). Every other event leaves waiting robots asleep.
fn could_change_an_offer(event: &Event) -> bool {
    match event.kind {
        EventKind::TaskChanged => {
            event.data.get("state").and_then(Value::as_str) == Some(TaskState::Queued.as_str())
        }
        EventKind::TagChanged
        | EventKind::TagArchived
        | EventKind::TagRetagged
        | EventKind::LearnedChanged
        | EventKind::ReliabilityChanged
        | EventKind::RobotChanged => true,
        _ => false,
    }
}

async fn flush_sightings(state: &AppState) {
    let sightings = state.sightings.take();
    if sightings.is_empty() {
        return;
    }
    let result = async {
        let mut tx = state.db.begin_write().await?;
        inbox::record(&mut tx, &sightings).await?;
        tx.commit().await
    }
    .await;
    match result {
        Ok(()) => state.feed.committed(),
        Err(error) => {
            tracing::warn!(%error, n = sightings.len(), "could not record unknown EPCs in the inbox")
        }
    }
}

async fn prune_events(state: &AppState) {
    let result: sqlx::Result<u64> = async {
        let mut tx = state.db.begin_write().await?;
        let pruned = events::prune(&mut tx).await?;
        tx.commit().await?;
        Ok(pruned)
    }
    .await;
    match result {
        Ok(0) => {}
        Ok(pruned) => tracing::debug!(pruned, "dropped old change-feed events"),
        Err(error) => tracing::warn!(%error, "could not drop old change-feed events"),
    }
}

/// Cancels the tasks that expired, then returns the tasks of robots whose lease ran out (from
/// its stored expiry, so also for leases given before a restart) to the queue, or fails them
/// after their last attempt.
pub async fn expire_leases(state: &AppState) {
    let now = state.clock.now();
    // A look on the read pool first: the sweep takes the write lock only when it has work.
    match tasks::any_overdue(state.db.reader(), now).await {
        Ok(true) => {}
        Ok(false) => return,
        Err(error) => return tracing::warn!(%error, "cannot look for leases that ran out"),
    }
    let result = async {
        let mut tx = state.db.begin_write().await?;
        let expired = tasks::expire(&mut tx, now).await?;
        let changed = tasks::expire_leases(&mut tx, now).await?;
        tx.commit().await?;
        Ok::<_, sqlx::Error>((expired, changed))
    }
    .await;
    match result {
        Ok((expired, changed)) => {
            for task in &expired {
                tracing::info!(task = %task.id, "a task expired before a robot did it");
            }
            for task in &changed {
                tracing::info!(task = %task.id, state = %task.state, "a robot's lease ran out");
            }
            // Waiting robots hear of tasks back in the queue from the feed's pump.
            state.feed.committed();
        }
        Err(error) => tracing::warn!(%error, "could not expire tasks or return lapsed leases"),
    }
}

async fn flush_presence(state: &AppState) {
    let seen = state.presence.take_unflushed();
    if seen.is_empty() {
        return;
    }
    if let Err(error) = robots::record_presence(&state.db, &seen).await {
        tracing::warn!(%error, "could not store when robots were last seen");
    }
}
