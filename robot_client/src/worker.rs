//! A simulated robot that does what caretakers ask (DESIGN §8): it claims the next task the
//! registry offers it, runs it in the simulator exactly as `pps-robot run` does (the four
//! phases, the trial through the outbox, the task's id in the trial's `measurements.task`),
//! heartbeats while it works, finishes the task with the trial and claims the next. A task on
//! a tag that no device of its simulated room carries it declines at once, saying so, so the
//! registry offers it to the other robots and the caretaker reads why; so does a task it tried
//! and stopped before acting on (the tag not found, say), with what stopped it.
//!
//! `pps-robot work` parses its settings and prints what [`Worker::work`] says; the loop, its
//! retries and the lease live here.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use pps_schema::{Outcome, decline_reason};

use crate::experiment::{SimulatedTrial, flush_until_stored, run_simulated};
use crate::registry::{QueuedTask, RegistryClient, RegistryError, retry};
use crate::sim::{DeviceKind, RoomOptions, SimBody};
use crate::task::{TaskConfig, TaskReport};

/// The longest one claim waits for a task: short enough that a stop request is answered soon,
/// since a claim the registry answers is never dropped half-way (its task would be stranded
/// until its lease ran out).
const CLAIM_WAIT: Duration = Duration::from_secs(5);
/// How long finishing a done task is tried while the registry is away: within the lease, which
/// the heartbeat no longer renews once the trial is done.
const FINISH_FOR: Duration = Duration::from_secs(20);
/// Why the simulated robot declines a task on a tag it cannot find, in the caretaker's words.
const NOT_IN_THE_ROOM: &str = "no device in its simulated room has this tag";

/// What the worker has to say: how a task went, or why it pauses or stops.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Said {
    Task(String),
    Pause(String),
}

/// One simulated robot and how long it works.
#[derive(Debug, Clone)]
pub struct Worker {
    pub registry: RegistryClient,
    /// The robot's body, as start-up found its class.
    pub body: SimBody,
    pub room: RoomOptions,
    /// Seed of the simulated world's noise; the n-th task runs with `seed + n`.
    pub seed: u64,
    /// Stop after this many tasks.
    pub max_tasks: Option<u64>,
    /// Stop once no task came for this long.
    pub idle_exit: Option<Duration>,
    /// Send each trial with a picture of what the camera saw.
    pub picture: bool,
}

impl Worker {
    /// Claims and does tasks until `stopping` is set (looked at between tasks), `max_tasks`
    /// are done or none came for `idle_exit`; `say` hears of every task and every pause.
    /// Returns how many tasks it did.
    pub async fn work(
        &self,
        stopping: &AtomicBool,
        mut say: impl FnMut(Said),
    ) -> anyhow::Result<u64> {
        let mut done = 0u64;
        let mut idle_since = Instant::now();
        let mut waits = retry::waits();
        while !stopping.load(Ordering::Acquire) && self.max_tasks.is_none_or(|max| done < max) {
            let idle_left = self.idle_exit.map(|idle| idle.saturating_sub(idle_since.elapsed()));
            let task = match self
                .registry
                .claim_task(idle_left.map_or(CLAIM_WAIT, |left| left.min(CLAIM_WAIT)))
                .await
            {
                Ok(Some(task)) => {
                    waits = retry::waits();
                    task
                }
                Ok(None) if idle_left.is_some_and(|left| left <= CLAIM_WAIT) => {
                    let idle = self.idle_exit.unwrap_or_default().as_secs_f64();
                    say(Said::Pause(format!("no task came for {idle} s; stopping")));
                    break;
                }
                Ok(None) => {
                    waits = retry::waits();
                    continue;
                }
                Err(error @ RegistryError::Unreachable(_)) => {
                    let wait = waits.next().unwrap_or(retry::LONGEST_WAIT);
                    let seconds = wait.as_secs_f64();
                    say(Said::Pause(format!("{error}; claiming again in {seconds:.1} s")));
                    #[allow(
                        clippy::disallowed_methods,
                        reason = "back-off while the registry is unreachable"
                    )]
                    tokio::time::sleep(wait).await;
                    continue;
                }
                Err(error) => return Err(anyhow::anyhow!("cannot claim a task: {error}")),
            };
            let seed = self.seed.wrapping_add(done);
            say(Said::Task(
                work_on(&self.registry, &task, self.body, self.room, seed, self.picture).await?,
            ));
            done += 1;
            idle_since = Instant::now();
        }
        Ok(done)
    }
}

/// Why the robot gave a task back after trying it, as a decline: what it could not do in a
/// caretaker's words, with what they can do about it when the robot knows; and, apart, what the
/// phase that stopped it said, for whoever looks further.
fn stopped_before_acting(report: &TaskReport) -> GivenBack {
    let Some(phase) = report.phases.iter().find(|p| !p.ok) else {
        return GivenBack { reason: "it tried and recorded no trial".to_owned(), detail: None };
    };
    let said = phase.lines.last().map_or("", String::as_str);
    // With advice, the robot's own words go apart; without, they are the reason.
    let (words, detail) = match &phase.advice {
        Some(advice) => (advice.as_str(), Some(said)),
        None => (said, None),
    };
    GivenBack {
        reason: decline_reason(&format!("it tried and could not {}: {words}", phase.could_not())),
        detail: detail.map(decline_reason).filter(|said| !said.is_empty()),
    }
}

/// A task given back: why, in a caretaker's words, and what the robot itself said.
struct GivenBack {
    reason: String,
    detail: Option<String>,
}

/// Runs one claimed task in a fresh simulated room and ends it; returns a line saying how.
async fn work_on(
    registry: &RegistryClient,
    task: &QueuedTask,
    body: SimBody,
    room: RoomOptions,
    seed: u64,
    picture: bool,
) -> anyhow::Result<String> {
    let said = format!("task {}: {} on {}", task.id, task.action, task.epc);
    let Some(device) = DeviceKind::ALL.into_iter().find(|d| d.epc() == task.epc) else {
        return Ok(match registry.decline_task(task.id, NOT_IN_THE_ROOM, None).await {
            Ok(_) => format!("{said}: declined: {NOT_IN_THE_ROOM}"),
            Err(error) => format!(
                "{said}: {NOT_IN_THE_ROOM}, but the decline did not reach the registry ({error}); \
                 its lease will run out and the task go to another robot"
            ),
        });
    };
    let heartbeat = tokio::spawn(keep_lease(registry.clone(), task.clone()));
    let trial =
        SimulatedTrial { room, seed, body, ..SimulatedTrial::new(device, &task.action, None) };
    let config = TaskConfig { task: Some(task.id), picture, ..TaskConfig::default() };
    let result = run_simulated(&trial, registry, &config).await;
    heartbeat.abort();
    let result = result?;
    let (Some(trial), Some(outcome)) = (result.report.trial, result.report.outcome) else {
        // Said to the registry at once, not left for the lease to run out: the caretaker reads
        // why beside the task, and the task goes to the other robots or says none can do it.
        let GivenBack { reason: why, detail } = stopped_before_acting(&result.report);
        return Ok(match registry.decline_task(task.id, &why, detail.as_deref()).await {
            Ok(_) => match &detail {
                Some(detail) => format!("{said}: declined after trying: {why} (it said: {detail})"),
                None => format!("{said}: declined after trying: {why}"),
            },
            Err(error) => format!(
                "{said}: stopped before acting ({why}), but the decline did not reach the \
                 registry ({error}); its lease will run out and the task go back to the queue"
            ),
        });
    };
    // The registry checks the trial when the task is finished: it must be stored by then.
    flush_until_stored(registry).await?;
    let (started, mut waits) = (Instant::now(), retry::waits());
    Ok(loop {
        match registry.finish_task(task.id, trial, outcome).await {
            Ok(ended) => {
                break format!(
                    "{said}: {} (trial {trial}, {})",
                    ended.state,
                    outcome_words(outcome)
                );
            }
            // Done but not said: keep saying it while the lease lasts, or another robot redoes it.
            Err(RegistryError::Unreachable(_)) if started.elapsed() < FINISH_FOR => {
                #[allow(
                    clippy::disallowed_methods,
                    reason = "back-off while the registry is unreachable"
                )]
                tokio::time::sleep(waits.next().unwrap_or(retry::LONGEST_WAIT)).await;
            }
            Err(error) => {
                break format!(
                    "{said}: trial {trial} recorded, but the task was not finished: {error}"
                );
            }
        }
    })
}

fn outcome_words(outcome: Outcome) -> &'static str {
    match outcome {
        Outcome::Success => "the detector saw it work",
        Outcome::Failure => "the detector saw it fail",
        Outcome::Aborted => "aborted",
        Outcome::Error => "an error stopped it",
    }
}

/// Heartbeats until aborted, or until the registry says the lease was lost.
async fn keep_lease(registry: RegistryClient, task: QueuedTask) {
    let mut every = task.heartbeat_every();
    loop {
        #[allow(clippy::disallowed_methods, reason = "a heartbeat's period")]
        tokio::time::sleep(every).await;
        match registry.heartbeat_task(task.id).await {
            Ok(extended) => every = extended.heartbeat_every(),
            Err(error) if error.status() == Some(409) => {
                eprintln!("task {}: {error}", task.id);
                return;
            }
            // Passing trouble: the lease outlasts a few lost beats.
            Err(error) => eprintln!("task {}: heartbeat failed: {error}", task.id),
        }
    }
}
