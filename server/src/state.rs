//! The state every request handler shares.

use std::sync::Arc;

use crate::auth::cache::TokenCache;
use crate::auth::login_throttle::LoginThrottle;
use crate::clock::Clock;
use crate::feed::ChangeFeed;
use crate::ops::bridge_status::BridgeStatus;
use crate::ops::metrics::Metrics;
use crate::robots::presence::Presence;
use crate::robots::sightings::Sightings;
use crate::robots::waiting_line::WaitingLine;
use crate::store::db::Db;
use crate::tags::effective_cache::EffectiveCache;
use crate::transport::AnswerTurns;
use crate::trial_history::writer::TrialWriter;

/// The shared state, behind one `Arc`: every request clones it (the router hands each handler
/// and middleware its own copy), and one reference count bumped per clone is far cheaper on
/// the hot path, with every core at it, than one per field.
#[derive(Debug, Clone)]
pub struct AppState(Arc<Shared>);

#[derive(Debug)]
pub struct Shared {
    pub db: Db,
    /// The time every decision reads: leases, expiry, throttles, sessions, presence.
    pub clock: Clock,
    pub tokens: Arc<TokenCache>,
    /// Recent failed password logins, to slow down guessing.
    pub login_throttle: Arc<LoginThrottle>,
    /// Merged entries served on the robots' hot path.
    pub effective: Arc<EffectiveCache>,
    pub feed: Arc<ChangeFeed>,
    pub presence: Arc<Presence>,
    /// Unknown EPCs robots read, on their way to the inbox.
    pub sightings: Arc<Sightings>,
    pub trials: TrialWriter,
    /// Robots waiting for a task, and the lease a claim gives.
    pub tasks: Arc<WaitingLine>,
    pub metrics: Arc<Metrics>,
    /// Turns at building answers of megabytes, fair between client addresses.
    pub heavy_answers: Arc<AnswerTurns>,
    /// Whether this process runs the Home Assistant bridge and is connected.
    pub home_assistant: Arc<BridgeStatus>,
    /// Pictures kept per tag: a new one removes the bytes of the oldest beyond this.
    pub pictures_per_tag: u32,
}

impl std::ops::Deref for AppState {
    type Target = Shared;

    fn deref(&self) -> &Shared {
        &self.0
    }
}

impl AppState {
    /// The state for a registry on `db` on the system clock; starts the trial writer, so it
    /// needs a Tokio runtime.
    pub fn new(db: Db) -> Self {
        Self::on_clock(db, Clock::System)
    }

    /// [`Self::new`] reading the time from `clock` (tests move a manual one).
    pub fn on_clock(db: Db, clock: Clock) -> Self {
        let feed = Arc::new(ChangeFeed::default());
        let effective = Arc::new(EffectiveCache::default());
        let trials = TrialWriter::start(db.clone(), clock.clone(), feed.clone(), effective.clone());
        Self(Arc::new(Shared {
            db,
            clock,
            tokens: Arc::default(),
            login_throttle: Arc::default(),
            effective,
            feed,
            presence: Arc::default(),
            sightings: Arc::default(),
            trials,
            tasks: Arc::default(),
            metrics: Arc::default(),
            heavy_answers: Arc::new(AnswerTurns::for_this_machine()),
            home_assistant: Arc::default(),
            pictures_per_tag: crate::trials::picture::DEFAULT_PICTURES_PER_TAG,
        }))
    }

    /// The state with claims holding a task for `lease` (DESIGN leaves the lease to the
    /// registry; tests of dead robots use a short one). Set before the state is shared.
    pub fn with_task_lease(mut self, lease: std::time::Duration) -> Self {
        let shared = Arc::get_mut(&mut self.0).expect("the task lease is set before serving");
        shared.tasks = Arc::new(WaitingLine::new(lease, shared.tasks.max_held()));
        self
    }

    /// The state letting one robot hold at most `tasks` tasks at once. Set before the state is
    /// shared.
    pub fn with_max_tasks_per_robot(mut self, tasks: usize) -> Self {
        let shared = Arc::get_mut(&mut self.0).expect("the task cap is set before serving");
        shared.tasks = Arc::new(WaitingLine::new(shared.tasks.lease(), tasks));
        self
    }

    /// The state keeping the newest `pictures` pictures of each tag. Set before the state is
    /// shared.
    pub fn with_pictures_per_tag(mut self, pictures: u32) -> Self {
        let shared =
            Arc::get_mut(&mut self.0).expect("the picture retention is set before serving");
        shared.pictures_per_tag = pictures;
        self
    }
}
