//! Durable trial writes with group commit.
//!
//! Every trial is acknowledged only after the transaction holding it has committed (and, with
//! `synchronous=FULL`, reached the disk). One task owns the writing: it takes every trial that
//! queued up while the previous commit was being flushed and commits them together, so many
//! robots writing at once share each fsync instead of paying one each.

use std::collections::{BTreeSet, HashMap, HashSet};
use std::sync::Arc;

use pps_schema::{Epc, RobotId, Trial};
use serde_json::{Value, json};
use sqlx::AnyConnection;
use time::OffsetDateTime;
use tokio::sync::{mpsc, oneshot};
use uuid::Uuid;

use crate::clock::Clock;
use crate::feed::ChangeFeed;
use crate::learning::{self, TrialGroup};
use crate::learning::{colour, size};
use crate::store;
use crate::store::db::{Db, Unwritable};
use crate::store::events::{self, EventKind};
use crate::store::trials::{self, NewTrial, TrialRow};
use crate::tags::effective_cache::EffectiveCache;
use crate::trial_history::retention;

/// Trials committed together at most.
const MAX_BATCH: usize = 512;
/// Trials waiting for the writer before new requests wait for room.
const QUEUE: usize = 4096;

/// A trial that passed validation, ready to store.
#[derive(Debug, Clone)]
pub struct CheckedTrial {
    pub trial: Trial,
    /// The trial as submitted; a retry must match it exactly.
    pub body: Value,
}

/// A trial that is stored.
#[derive(Debug)]
pub enum Recorded {
    New(TrialRow),
    /// The same trial was stored before: the retry changed nothing.
    Repeat(TrialRow),
}

/// Why a trial was not stored.
#[derive(Debug, thiserror::Error)]
pub enum TrialRejection {
    #[error("another trial is stored under this id")]
    Conflict(TrialRow),
    #[error("no tag has this EPC")]
    UnknownTag,
    #[error("the tag is archived")]
    ArchivedTag,
    #[error("the EPC was retired; the tag now has EPC {0}")]
    RetiredTag(Epc),
    #[error("the trial could not be stored: {0}")]
    Database(Arc<sqlx::Error>),
    #[error("the registry is shutting down")]
    ShuttingDown,
}

type Reply = oneshot::Sender<Result<Recorded, TrialRejection>>;

#[derive(Debug, Clone)]
pub struct TrialWriter {
    queue: mpsc::Sender<(CheckedTrial, Reply)>,
}

impl TrialWriter {
    /// Starts the writing task (needs a Tokio runtime).
    pub fn start(db: Db, clock: Clock, feed: Arc<ChangeFeed>, cache: Arc<EffectiveCache>) -> Self {
        let (queue, incoming) = mpsc::channel(QUEUE);
        tokio::spawn(run(db, clock, incoming, feed, cache));
        Self { queue }
    }

    /// Stores a trial; returns once it is durable.
    pub async fn record(&self, trial: CheckedTrial) -> Result<Recorded, TrialRejection> {
        let (reply, answer) = oneshot::channel();
        self.queue.send((trial, reply)).await.map_err(|_| TrialRejection::ShuttingDown)?;
        answer.await.map_err(|_| TrialRejection::ShuttingDown)?
    }
}

async fn run(
    db: Db,
    clock: Clock,
    mut incoming: mpsc::Receiver<(CheckedTrial, Reply)>,
    feed: Arc<ChangeFeed>,
    cache: Arc<EffectiveCache>,
) {
    let mut batch = Vec::with_capacity(MAX_BATCH);
    while incoming.recv_many(&mut batch, MAX_BATCH).await > 0 {
        let trials: Vec<&CheckedTrial> = batch.iter().map(|(trial, _)| trial).collect();
        match commit(&db, &clock, &trials).await {
            Ok(stored) => answer(batch.drain(..), stored, &feed, &cache),
            // One trial's problem must stay its own: commit each alone, so only it fails.
            Err(error) if batch.len() > 1 && Unwritable::of(&error).is_none() => {
                tracing::warn!(%error, trials = batch.len(), "a batch of trials failed; committing them one by one");
                for (trial, reply) in batch.drain(..) {
                    match commit(&db, &clock, &[&trial]).await {
                        Ok(stored) => answer([(trial, reply)].into_iter(), stored, &feed, &cache),
                        Err(error) => refuse([(trial, reply)].into_iter(), error),
                    }
                }
            }
            Err(error) => refuse(batch.drain(..), error),
        }
    }
}

type Stored = (Vec<Result<Recorded, TrialRejection>>, BTreeSet<Epc>);

/// Answers the robots of a committed batch, after the caches and the feed have heard of it.
fn answer(
    batch: impl Iterator<Item = (CheckedTrial, Reply)>,
    (results, relearned): Stored,
    feed: &ChangeFeed,
    cache: &EffectiveCache,
) {
    for epc in relearned {
        cache.forget_tag(epc.as_hex());
    }
    feed.committed();
    for ((_, reply), result) in batch.zip(results) {
        let _ = reply.send(result);
    }
}

fn refuse(batch: impl ExactSizeIterator<Item = (CheckedTrial, Reply)>, error: sqlx::Error) {
    if Unwritable::of(&error).is_none() {
        tracing::error!(%error, trials = batch.len(), "trials could not be committed");
    }
    let error = Arc::new(error);
    for (_, reply) in batch {
        let _ = reply.send(Err(TrialRejection::Database(error.clone())));
    }
}

/// Stores a batch in one transaction; per-trial rejections do not fail the others.
///
/// The batch's time is what every waiting robot pays, so it is kept to a few statements
/// whatever its size: each tag and robot is looked up once, and all new trials and their
/// events are inserted with one statement each.
async fn commit(db: &Db, clock: &Clock, batch: &[&CheckedTrial]) -> sqlx::Result<Stored> {
    // Serialised before the write lock is taken.
    let bodies: Vec<String> = batch.iter().map(|checked| checked.body.to_string()).collect();
    let mut tx = db.begin_write().await?;
    let received_at = clock.now();
    let known = Known::look_up(&mut tx, batch).await?;
    let seqs = insert_on_active_tags(&mut tx, batch, &bodies, &known, received_at).await?;
    let sorted = sort_out(&mut tx, batch, bodies, &known, &seqs, received_at).await?;
    announce(&mut tx, sorted.recorded).await?;
    let relearned = learning::update(&mut tx, &sorted.groups).await?;
    tx.commit().await?;
    Ok((sorted.results, relearned))
}

/// What the batch's trials need to know of their tags and robots, each looked up once.
struct Known<'a> {
    tags: HashMap<&'a Epc, Result<(), TagProblem>>,
    classes: HashMap<&'a RobotId, Option<String>>,
}

impl<'a> Known<'a> {
    async fn look_up(tx: &mut AnyConnection, batch: &[&'a CheckedTrial]) -> sqlx::Result<Self> {
        let mut known = Self { tags: HashMap::new(), classes: HashMap::new() };
        for CheckedTrial { trial, .. } in batch {
            if !known.tags.contains_key(&trial.epc) {
                known.tags.insert(&trial.epc, check_tag(tx, &trial.epc).await?);
            }
            if !known.classes.contains_key(&trial.robot) {
                let class = store::robots::class_of(tx, &trial.robot).await?;
                known.classes.insert(&trial.robot, class);
            }
        }
        Ok(known)
    }

    fn class_of(&self, trial: &Trial) -> Option<&str> {
        self.classes[&trial.robot].as_deref()
    }
}

/// Inserts the trials on active tags, in as few statements as the driver allows; returns the
/// sequence numbers of those that were new. A retry of a trial stored before its tag was
/// archived is still a retry, so the others are sorted out afterwards rather than refused.
async fn insert_on_active_tags(
    tx: &mut AnyConnection,
    batch: &[&CheckedTrial],
    bodies: &[String],
    known: &Known<'_>,
    received_at: OffsetDateTime,
) -> sqlx::Result<HashMap<Uuid, i64>> {
    let insertable: Vec<NewTrial<'_>> = batch
        .iter()
        .zip(bodies)
        .filter(|(checked, _)| known.tags[&checked.trial.epc].is_ok())
        .map(|(checked, body)| NewTrial {
            trial: &checked.trial,
            robot_class: known.class_of(&checked.trial),
            received_at,
            body,
        })
        .collect();
    let mut seqs = HashMap::new();
    for chunk in insertable.chunks(trials::INSERT_CHUNK) {
        seqs.extend(trials::insert_new(tx, chunk).await?);
    }
    Ok(seqs)
}

/// Each trial's answer, and what the new ones announce and teach.
struct Sorted<'a> {
    results: Vec<Result<Recorded, TrialRejection>>,
    recorded: Vec<(i64, &'a Trial)>,
    groups: BTreeSet<TrialGroup>,
}

/// Sorts the batch into new trials, retries and conflicts, and refusals of their tag.
async fn sort_out<'a>(
    tx: &mut AnyConnection,
    batch: &[&'a CheckedTrial],
    bodies: Vec<String>,
    known: &Known<'_>,
    seqs: &HashMap<Uuid, i64>,
    received_at: OffsetDateTime,
) -> sqlx::Result<Sorted<'a>> {
    let mut sorted = Sorted {
        results: Vec::with_capacity(batch.len()),
        recorded: Vec::new(),
        groups: BTreeSet::new(),
    };
    let mut seen: HashSet<Uuid> = HashSet::with_capacity(batch.len());
    for (CheckedTrial { trial, body: submitted }, body) in batch.iter().copied().zip(bodies) {
        // Only the first of duplicate ids in a batch was inserted; the rest are retries.
        let first = seen.insert(trial.id);
        let Some(&seq) = seqs.get(&trial.id).filter(|_| first) else {
            sorted.results.push(not_inserted(tx, trial, submitted, known).await?);
            continue;
        };
        let robot_class = known.class_of(trial).map(str::to_owned);
        sorted.recorded.push((seq, trial));
        sorted.groups.insert(TrialGroup {
            epc: trial.epc.clone(),
            action: trial.action.clone(),
            behavior: trial.behavior.clone(),
            robot_class: robot_class.clone(),
            relearn: learning::teaches(submitted.get("measurements"))
                || colour::teaches(submitted)
                || size::teaches(submitted),
        });
        sorted.results.push(Ok(Recorded::New(TrialRow {
            seq,
            id: trial.id,
            epc: trial.epc.clone(),
            robot: trial.robot.clone(),
            robot_class,
            action: trial.action.clone(),
            outcome: trial.outcome.as_str().to_owned(),
            confirmed: trial.confirmed,
            purpose: trial.purpose.as_str().to_owned(),
            received_at,
            body,
            has_picture: false,
        })));
    }
    Ok(sorted)
}

/// The answer to a trial that was not inserted: a retry of the stored one, a conflict with
/// it, or its tag's refusal.
async fn not_inserted(
    tx: &mut AnyConnection,
    trial: &Trial,
    submitted: &Value,
    known: &Known<'_>,
) -> sqlx::Result<Result<Recorded, TrialRejection>> {
    Ok(match trials::find(tx, &trial.id).await? {
        Some(existing) if retention::same_submission(&existing.submitted(), submitted) => {
            Ok(Recorded::Repeat(existing))
        }
        Some(existing) => Err(TrialRejection::Conflict(existing)),
        None => Err(known.tags[&trial.epc].clone().err().map_or_else(
            || TrialRejection::Database(Arc::new(sqlx::Error::RowNotFound)),
            TagProblem::rejection,
        )),
    })
}

/// Puts the new trials in the feed, in the order the registry stored them.
async fn announce(tx: &mut AnyConnection, mut recorded: Vec<(i64, &Trial)>) -> sqlx::Result<()> {
    recorded.sort_by_key(|(seq, _)| *seq);
    let announcements: Vec<Value> = recorded
        .iter()
        .map(|(seq, trial)| {
            json!({
                "trial": trial.id, "epc": trial.epc.as_hex(), "robot": trial.robot,
                "action": trial.action, "outcome": trial.outcome.as_str(), "seq": seq
            })
        })
        .collect();
    events::append_all(tx, EventKind::TrialRecorded, &announcements).await
}

/// Why a tag takes no trials.
#[derive(Debug, Clone)]
enum TagProblem {
    Unknown,
    Archived,
    Retired(Epc),
}

impl TagProblem {
    fn rejection(self) -> TrialRejection {
        match self {
            Self::Unknown => TrialRejection::UnknownTag,
            Self::Archived => TrialRejection::ArchivedTag,
            Self::Retired(successor) => TrialRejection::RetiredTag(successor),
        }
    }
}

/// A trial must name a registered, active tag.
async fn check_tag(conn: &mut AnyConnection, epc: &Epc) -> sqlx::Result<Result<(), TagProblem>> {
    Ok(match store::tags::is_archived(conn, epc).await? {
        Some(false) => Ok(()),
        Some(true) => Err(TagProblem::Archived),
        None => match store::retired::successor(conn, epc).await? {
            Some(successor) => Err(TagProblem::Retired(successor)),
            None => Err(TagProblem::Unknown),
        },
    })
}
