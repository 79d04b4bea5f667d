//! Durable trial writes with group commit.
//!
//! Every trial is acknowledged only after the transaction holding it has committed (and, with
//! `synchronous=FULL`, reached the disk). One task owns the writing: it takes every trial that
//! queued up while the previous commit was being flushed and commits them together, so many
//! robots writing at once share each fsync instead of paying one each.

use std::collections::{BTreeSet, HashMap, HashSet};
use std::sync::Arc;

use serde_json::{Value, json};
use tokio::sync::{mpsc, oneshot};

use crate::db::{Db, Unwritable};
use crate::effective_cache::EffectiveCache;
use crate::feed::ChangeFeed;
use crate::learning::{self, TrialGroup};
use crate::store::events::{self, EventKind};
use crate::store::trials::{self, TrialRow};
use crate::{clock, retention, store};

/// Trials committed together at most.
const MAX_BATCH: usize = 512;
/// Trials waiting for the writer before new requests wait for room.
const QUEUE: usize = 4096;

/// A trial that passed validation, ready to store.
#[derive(Debug, Clone)]
pub struct CheckedTrial {
    pub id: String,
    pub epc: String,
    pub robot: String,
    pub action: String,
    pub behavior: String,
    pub outcome: String,
    pub confirmed: Option<bool>,
    pub started_at: String,
    pub finished_at: String,
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
    RetiredTag(String),
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
    pub fn start(db: Db, feed: Arc<ChangeFeed>, cache: Arc<EffectiveCache>) -> Self {
        let (queue, incoming) = mpsc::channel(QUEUE);
        tokio::spawn(run(db, incoming, feed, cache));
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
    mut incoming: mpsc::Receiver<(CheckedTrial, Reply)>,
    feed: Arc<ChangeFeed>,
    cache: Arc<EffectiveCache>,
) {
    let mut batch = Vec::with_capacity(MAX_BATCH);
    while incoming.recv_many(&mut batch, MAX_BATCH).await > 0 {
        let trials: Vec<&CheckedTrial> = batch.iter().map(|(trial, _)| trial).collect();
        match commit(&db, &trials).await {
            Ok(stored) => answer(batch.drain(..), stored, &feed, &cache),
            // One trial's problem must stay its own: commit each alone, so only it fails.
            Err(error) if batch.len() > 1 && Unwritable::of(&error).is_none() => {
                tracing::warn!(%error, trials = batch.len(), "a batch of trials failed; committing them one by one");
                for (trial, reply) in batch.drain(..) {
                    match commit(&db, &[&trial]).await {
                        Ok(stored) => answer([(trial, reply)].into_iter(), stored, &feed, &cache),
                        Err(error) => refuse([(trial, reply)].into_iter(), error),
                    }
                }
            }
            Err(error) => refuse(batch.drain(..), error),
        }
    }
}

type Stored = (Vec<Result<Recorded, TrialRejection>>, BTreeSet<String>);

/// Answers the robots of a committed batch, after the caches and the feed have heard of it.
fn answer(
    batch: impl Iterator<Item = (CheckedTrial, Reply)>,
    (results, relearned): Stored,
    feed: &ChangeFeed,
    cache: &EffectiveCache,
) {
    for epc in relearned {
        cache.forget_tag(&epc);
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
async fn commit(db: &Db, batch: &[&CheckedTrial]) -> sqlx::Result<Stored> {
    // Serialised before the write lock is taken.
    let bodies: Vec<String> = batch.iter().map(|trial| trial.body.to_string()).collect();
    let mut tx = db.begin_write().await?;
    let received_at = clock::now();
    let mut tags: HashMap<&str, Result<(), TagProblem>> = HashMap::new();
    let mut classes: HashMap<&str, Option<String>> = HashMap::new();
    for trial in batch {
        if !tags.contains_key(trial.epc.as_str()) {
            tags.insert(&trial.epc, check_tag(&mut tx, &trial.epc).await?);
        }
        if !classes.contains_key(trial.robot.as_str()) {
            let class = store::robots::class_of(&mut tx, &trial.robot).await?;
            classes.insert(&trial.robot, class);
        }
    }

    // Trials on active tags; a retry of a trial stored before its tag was archived is still a
    // retry, so the others are looked up below rather than refused at once.
    let insertable: Vec<usize> =
        (0..batch.len()).filter(|&i| tags[batch[i].epc.as_str()].is_ok()).collect();
    let mut seqs: HashMap<String, i64> = HashMap::new();
    for chunk in insertable.chunks(INSERT_CHUNK) {
        // A second trial with the same id in one batch meets the first: it is a retry then.
        let statement = format!(
            "insert into trials (id, epc, robot, robot_class, action, behavior, outcome, \
             confirmed, started_at, finished_at, received_at, body) values {} \
             on conflict (id) do nothing returning id, seq",
            store::placeholders::rows(chunk.len(), 12)
        );
        let mut insert = sqlx::query_as(sqlx::AssertSqlSafe(statement));
        for &i in chunk {
            let trial = batch[i];
            insert = insert
                .bind(&trial.id)
                .bind(&trial.epc)
                .bind(&trial.robot)
                .bind(classes[trial.robot.as_str()].as_deref())
                .bind(&trial.action)
                .bind(&trial.behavior)
                .bind(&trial.outcome)
                .bind(trial.confirmed.map(i64::from))
                .bind(&trial.started_at)
                .bind(&trial.finished_at)
                .bind(&received_at)
                .bind(&bodies[i]);
        }
        let inserted: Vec<(String, i64)> = insert.fetch_all(&mut *tx).await?;
        seqs.extend(inserted);
    }

    let mut results = Vec::with_capacity(batch.len());
    let mut recorded: Vec<(i64, &CheckedTrial)> = Vec::new();
    let mut groups = BTreeSet::new();
    let mut seen: HashSet<&str> = HashSet::with_capacity(batch.len());
    for (trial, body) in batch.iter().zip(bodies) {
        let robot_class = classes[trial.robot.as_str()].clone();
        // Only the first of duplicate ids in a batch was inserted; the rest are retries.
        let first = seen.insert(trial.id.as_str());
        let Some(&seq) = seqs.get(&trial.id).filter(|_| first) else {
            results.push(match trials::find(&mut tx, &trial.id).await? {
                Some(existing)
                    if retention::same_submission(&existing.submitted(), &trial.body) =>
                {
                    Ok(Recorded::Repeat(existing))
                }
                Some(existing) => Err(TrialRejection::Conflict(existing)),
                None => Err(tags[trial.epc.as_str()].clone().err().map_or_else(
                    || TrialRejection::Database(Arc::new(sqlx::Error::RowNotFound)),
                    TagProblem::rejection,
                )),
            });
            continue;
        };
        recorded.push((seq, trial));
        groups.insert(TrialGroup {
            epc: trial.epc.clone(),
            action: trial.action.clone(),
            behavior: trial.behavior.clone(),
            robot_class: robot_class.clone().unwrap_or_default(),
            relearn: learning::teaches(trial.body.get("measurements")),
        });
        results.push(Ok(Recorded::New(TrialRow {
            seq,
            id: trial.id.clone(),
            epc: trial.epc.clone(),
            robot: trial.robot.clone(),
            robot_class,
            action: trial.action.clone(),
            outcome: trial.outcome.clone(),
            confirmed: trial.confirmed,
            received_at: received_at.clone(),
            body,
        })));
    }
    // The feed announces the trials in the order the registry stored them.
    recorded.sort_by_key(|(seq, _)| *seq);
    let announcements: Vec<Value> = recorded
        .iter()
        .map(|(seq, trial)| json!({ "trial": trial.id, "epc": trial.epc, "robot": trial.robot, "action": trial.action, "outcome": trial.outcome, "seq": seq }))
        .collect();
    events::append_all(&mut tx, EventKind::TrialRecorded, &announcements).await?;
    let relearned = learning::update(&mut tx, &groups).await?;
    tx.commit().await?;
    Ok((results, relearned))
}

/// Trials inserted by one statement at most (12 values each, well under SQLite's limit).
const INSERT_CHUNK: usize = 256;

/// Why a tag takes no trials.
#[derive(Debug, Clone)]
enum TagProblem {
    Unknown,
    Archived,
    Retired(String),
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
async fn check_tag(
    conn: &mut sqlx::AnyConnection,
    epc: &str,
) -> sqlx::Result<Result<(), TagProblem>> {
    Ok(match store::tags::is_archived(conn, epc).await? {
        Some(false) => Ok(()),
        Some(true) => Err(TagProblem::Archived),
        None => match store::retired::successor(conn, epc).await? {
            Some(successor) => Err(TagProblem::Retired(successor)),
            None => Err(TagProblem::Unknown),
        },
    })
}
