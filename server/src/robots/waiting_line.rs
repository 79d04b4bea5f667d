//! The robots waiting for a task, in the order they asked, and the signal that wakes them.
//!
//! A claim that finds nothing waits in line here until something happens that could change
//! its answer (a task asked for or back in the queue, a tag, robot or learned value changed),
//! so a new task reaches a waiting robot at once instead of at its next poll, and waiting
//! costs nothing while nothing changes. Each change is a new generation: it wakes the first
//! robot in line that has not looked since, and each robot that looked passes the turn to the
//! next one behind it that has not looked since. So a change costs at most one look per
//! waiting robot, a robot never looks twice at the same generation, and the robot that asked
//! first looks first: the fairness rule's tie-break. A robot leaving the line passes the turn
//! on too, and after a robot stepped aside for one ranked before it, its leaving is a change.
//! The line holds no task state: the database does, so a restart loses nothing but the line.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pps_schema::RobotId;
use tokio::sync::Notify;

/// How long a claim holds a task before it goes back to the queue, unless heartbeats extend it.
pub const DEFAULT_LEASE: Duration = Duration::from_secs(30);
/// Tasks one robot holds at once unless the registry is told otherwise: the one it works on,
/// and one more for a robot that restarted before its old lease ran out.
pub const DEFAULT_MAX_TASKS_PER_ROBOT: usize = 2;
/// Claims one robot may have waiting at once. A robot needs one; a few more cover claims it
/// gave up on (a dropped connection) whose wait has not ended yet.
pub const MAX_WAITING_PER_ROBOT: usize = 4;

/// One robot waiting in line.
#[derive(Debug, Clone)]
pub struct Waiter {
    /// Its place: lower asked earlier.
    pub arrival: u64,
    pub robot: RobotId,
    pub class: Option<String>,
    /// Whether it waits for a task; an instant claim leaves with nothing rather than wait.
    pub waits: bool,
    /// The generation of its last look.
    seen: u64,
    turn: Arc<Notify>,
}

/// The line, and how many changes there have been.
#[derive(Debug, Default)]
struct Line {
    waiters: BTreeMap<u64, Waiter>,
    generation: u64,
}

impl Line {
    /// Claims of `robot` waiting for a task.
    fn waiting_claims(&self, robot: &RobotId) -> usize {
        self.waiters.values().filter(|w| w.waits && &w.robot == robot).count()
    }

    /// Gives the turn to the first robot after `arrival` (exclusive) that has not looked at
    /// the current generation.
    fn wake_next_after(&self, arrival: Option<u64>) {
        let from = arrival.map_or(0, |a| a + 1);
        let next = self.waiters.range(from..).map(|(_, w)| w).find(|w| w.seen < self.generation);
        if let Some(waiter) = next {
            waiter.turn.notify_one();
        }
    }
}

/// A claim refused a place in line: its robot has [`MAX_WAITING_PER_ROBOT`] waiting already.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooManyWaiting;

/// The robots waiting for a task, and the queue's rules they wait under: how long a lease lasts
/// and how many tasks one robot may hold.
#[derive(Debug)]
pub struct WaitingLine {
    lease: Duration,
    max_held: usize,
    line: Mutex<Line>,
    arrivals: AtomicU64,
    /// A robot passed over a task for one ranked before it: when someone leaves the line,
    /// the others must look again.
    stepped_aside: AtomicBool,
    /// Looks for a task so far (each reads the database): what waiting costs.
    looks: AtomicU64,
}

impl Default for WaitingLine {
    fn default() -> Self {
        Self::new(DEFAULT_LEASE, DEFAULT_MAX_TASKS_PER_ROBOT)
    }
}

impl WaitingLine {
    pub fn new(lease: Duration, max_held: usize) -> Self {
        Self {
            lease,
            max_held: max_held.max(1),
            line: Mutex::default(),
            arrivals: AtomicU64::new(0),
            stepped_aside: AtomicBool::new(false),
            looks: AtomicU64::new(0),
        }
    }

    /// Looks for a task so far, by every claim.
    pub fn looks(&self) -> u64 {
        self.looks.load(Ordering::Relaxed)
    }

    /// How long a claim or a heartbeat holds a task.
    pub fn lease(&self) -> Duration {
        self.lease
    }

    /// How many tasks one robot may hold at once.
    pub fn max_held(&self) -> usize {
        self.max_held
    }

    /// How often leases that ran out are looked for: often enough that a dead robot's task is
    /// back in the queue soon after its lease, at most every second.
    pub fn sweep_every(&self) -> Duration {
        (self.lease / 4).clamp(Duration::from_millis(50), Duration::from_secs(1))
    }

    /// Something that could change a waiting robot's answer happened: a new generation, and
    /// the first robot in line gets its turn.
    pub fn changed(&self) {
        let mut line = self.lock();
        line.generation += 1;
        line.wake_next_after(None);
    }

    /// Puts `robot` in line until the returned place is dropped; `waits` when it will wait
    /// for a task rather than leave at once with nothing. A robot may wait with at most
    /// [`MAX_WAITING_PER_ROBOT`] claims at once.
    pub fn join(
        self: &Arc<Self>,
        robot: &RobotId,
        class: Option<&str>,
        waits: bool,
    ) -> Result<Place, TooManyWaiting> {
        let mut line = self.lock();
        if waits && line.waiting_claims(robot) >= MAX_WAITING_PER_ROBOT {
            return Err(TooManyWaiting);
        }
        let arrival = self.arrivals.fetch_add(1, Ordering::Relaxed);
        let turn = Arc::new(Notify::new());
        // Its first look comes after this, so it sees every change made so far.
        let seen = line.generation;
        let waiter = Waiter {
            arrival,
            robot: robot.clone(),
            class: class.map(str::to_owned),
            waits,
            seen,
            turn: turn.clone(),
        };
        line.waiters.insert(arrival, waiter);
        Ok(Place { board: self.clone(), arrival, turn })
    }

    /// Claims of `robot` waiting for a task now.
    pub fn waiting_claims(&self, robot: &RobotId) -> usize {
        self.lock().waiting_claims(robot)
    }

    /// Everyone in line who waits for a task, but the holder of `place`, first come first.
    /// Nobody steps aside for an instant claim: it would leave with nothing, and the task it
    /// was left would wait for the next claim.
    pub fn others(&self, place: &Place) -> Vec<Waiter> {
        self.lock()
            .waiters
            .values()
            .filter(|w| w.waits && w.arrival != place.arrival)
            .cloned()
            .collect()
    }

    /// Notes that a robot passed over a task for another in line.
    pub fn stepped_aside(&self) {
        self.stepped_aside.store(true, Ordering::Release);
    }

    /// Robots waiting now.
    pub fn waiting(&self) -> usize {
        self.lock().waiters.len()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Line> {
        self.line.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A robot's place in line. Leaving it (with a task or without) passes the turn on, or is a
/// change when a robot stepped aside for one ranked before it.
#[derive(Debug)]
pub struct Place {
    board: Arc<WaitingLine>,
    arrival: u64,
    turn: Arc<Notify>,
}

impl Place {
    pub fn arrival(&self) -> u64 {
        self.arrival
    }

    /// Notes that this robot looks for a task now; returns the generation the look sees (it
    /// starts after every change up to it).
    pub fn begin_look(&self) -> u64 {
        self.board.looks.fetch_add(1, Ordering::Relaxed);
        self.board.lock().generation
    }

    /// Notes that this robot looked at `generation` and passes the turn to the robot behind
    /// it that has not looked since.
    pub fn looked(&self, generation: u64) {
        let mut line = self.board.lock();
        if let Some(waiter) = line.waiters.get_mut(&self.arrival) {
            waiter.seen = waiter.seen.max(generation);
        }
        line.wake_next_after(Some(self.arrival));
    }

    /// Completes when it is this robot's turn and there is a change it has not looked at.
    /// A turn with nothing new is passed on at once.
    pub async fn next_change(&self) {
        loop {
            self.turn.notified().await;
            let line = self.board.lock();
            match line.waiters.get(&self.arrival) {
                Some(waiter) if waiter.seen < line.generation => return,
                _ => line.wake_next_after(Some(self.arrival)),
            }
        }
    }
}

impl Drop for Place {
    fn drop(&mut self) {
        let mut line = self.board.lock();
        line.waiters.remove(&self.arrival);
        if self.board.stepped_aside.swap(false, Ordering::AcqRel) {
            line.generation += 1;
            line.wake_next_after(None);
        } else {
            line.wake_next_after(Some(self.arrival));
        }
    }
}

#[cfg(test)]
mod tests {
    use std::future::Future;

    use super::*;

    /// The generation `place` may look at now, if it has been given its turn (without waiting).
    fn turn_now(place: &Place) -> Option<u64> {
        let turn = std::pin::pin!(place.next_change());
        let waker = std::task::Waker::noop();
        let ready = turn.poll(&mut std::task::Context::from_waker(waker)).is_ready();
        ready.then(|| place.board.lock().generation)
    }

    fn robot(id: &str) -> RobotId {
        RobotId::parse(id).unwrap()
    }

    #[test]
    fn a_change_wakes_the_first_in_line_who_passes_the_turn_back() {
        let board = Arc::new(WaitingLine::default());
        let first = board.join(&robot("a"), Some("el-e"), true).unwrap();
        let second = board.join(&robot("b"), None, true).unwrap();
        let third = board.join(&robot("c"), None, true).unwrap();
        let instant = board.join(&robot("d"), None, false).unwrap();
        let others: Vec<String> =
            board.others(&second).into_iter().map(|w| w.robot.to_string()).collect();
        assert_eq!(others, ["a", "c"], "nobody steps aside for an instant claim");
        drop(instant);
        assert!(turn_now(&first).is_none(), "nothing changed: nobody looks again");
        board.changed();
        assert_eq!(turn_now(&first), Some(1));
        assert!(turn_now(&second).is_none() && turn_now(&third).is_none(), "one look at a time");
        first.looked(1);
        assert_eq!(turn_now(&second), Some(1));
        drop(second);
        assert_eq!(turn_now(&third), Some(1), "leaving the line passes the turn on");
        third.looked(1);
        assert!(turn_now(&first).is_none(), "everyone looked at this change");
        assert_eq!(board.waiting(), 2);
        board.stepped_aside();
        drop(third);
        assert_eq!(turn_now(&first), Some(2), "after stepping aside, the front looks again");
        drop(first);
        assert_eq!(board.waiting(), 0);
    }

    #[test]
    fn a_robot_that_looked_at_the_newest_change_passes_a_late_turn_on() {
        let board = Arc::new(WaitingLine::default());
        let first = board.join(&robot("a"), None, true).unwrap();
        let second = board.join(&robot("b"), None, true).unwrap();
        board.changed();
        // The first robot looks at generation 1 before its turn arrives.
        let generation = board.lock().generation;
        first.looked(generation);
        assert_eq!(turn_now(&second), Some(1));
        second.looked(1);
        board.changed();
        assert_eq!(turn_now(&first), Some(2));
        first.looked(2);
        assert_eq!(turn_now(&second), Some(2));
    }

    #[test]
    fn one_robot_waits_with_at_most_a_few_claims_at_once() {
        let board = Arc::new(WaitingLine::default());
        let el_e = robot("el-e-1");
        let places: Vec<Place> =
            (0..MAX_WAITING_PER_ROBOT).map(|_| board.join(&el_e, None, true).unwrap()).collect();
        assert_eq!(board.join(&el_e, None, true).unwrap_err(), TooManyWaiting);
        assert!(board.join(&el_e, None, false).is_ok(), "an instant claim does not wait");
        assert!(board.join(&robot("el-e-2"), None, true).is_ok(), "another robot may wait");
        drop(places);
        assert!(board.join(&el_e, None, true).is_ok());
    }

    #[test]
    fn short_leases_are_swept_often_long_ones_every_second() {
        let board = |lease| WaitingLine::new(lease, DEFAULT_MAX_TASKS_PER_ROBOT);
        assert_eq!(board(Duration::from_secs(2)).sweep_every(), Duration::from_millis(500));
        assert_eq!(WaitingLine::default().sweep_every(), Duration::from_secs(1));
        assert_eq!(board(Duration::from_millis(100)).sweep_every(), Duration::from_millis(50));
    }
}
