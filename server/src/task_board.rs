//! The robots waiting for a task, in the order they asked, and the signal that wakes them.
//!
//! A claim that finds nothing waits in line here until it is its turn to look again, so a new
//! task reaches a waiting robot at once instead of at its next poll. A change (a task asked
//! for, a lease run out) wakes the first robot in line only; each robot that looked and took
//! nothing passes the turn to the one behind it while something is left to claim, and a robot
//! leaving the line passes it on too. So one new task costs one look, not one per waiting robot,
//! and the robot that asked first looks first: the fairness rule's tie-break.
//! The board holds no task state: the database does, so a restart loses nothing but the line.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pps_schema::RobotId;
use tokio::sync::Notify;

/// How long a claim holds a task before it goes back to the queue, unless heartbeats extend it.
pub const DEFAULT_LEASE: Duration = Duration::from_secs(30);

/// One robot waiting in line.
#[derive(Debug, Clone)]
pub struct Waiter {
    /// Its place: lower asked earlier.
    pub arrival: u64,
    pub robot: RobotId,
    pub class: Option<String>,
    /// Whether it waits for a task; an instant claim leaves with nothing rather than wait.
    pub waits: bool,
    turn: Arc<Notify>,
}

#[derive(Debug)]
pub struct TaskBoard {
    lease: Duration,
    line: Mutex<BTreeMap<u64, Waiter>>,
    arrivals: AtomicU64,
    /// A robot passed over a task for one ranked before it: when someone leaves the line,
    /// the others must look again.
    stepped_aside: AtomicBool,
}

impl Default for TaskBoard {
    fn default() -> Self {
        Self::new(DEFAULT_LEASE)
    }
}

impl TaskBoard {
    pub fn new(lease: Duration) -> Self {
        Self {
            lease,
            line: Mutex::default(),
            arrivals: AtomicU64::new(0),
            stepped_aside: AtomicBool::new(false),
        }
    }

    /// How long a claim or a heartbeat holds a task.
    pub fn lease(&self) -> Duration {
        self.lease
    }

    /// How often leases that ran out are looked for: often enough that a dead robot's task is
    /// back in the queue soon after its lease, at most every second.
    pub fn sweep_every(&self) -> Duration {
        (self.lease / 4).clamp(Duration::from_millis(50), Duration::from_secs(1))
    }

    /// Gives the first robot in line its turn: a task may be there for it or one behind it.
    pub fn changed(&self) {
        let first = self.lock().values().next().map(|w| w.turn.clone());
        if let Some(turn) = first {
            turn.notify_one();
        }
    }

    /// Gives the turn to the robot behind `place`, if any.
    pub fn pass_on(&self, place: &Place) {
        let next = self.lock().range(place.arrival + 1..).next().map(|(_, w)| w.turn.clone());
        if let Some(turn) = next {
            turn.notify_one();
        }
    }

    /// Puts `robot` in line until the returned place is dropped; `waits` when it will wait
    /// for a task rather than leave at once with nothing.
    pub fn join(self: &Arc<Self>, robot: &RobotId, class: Option<&str>, waits: bool) -> Place {
        let arrival = self.arrivals.fetch_add(1, Ordering::Relaxed);
        let turn = Arc::new(Notify::new());
        let waiter = Waiter {
            arrival,
            robot: robot.clone(),
            class: class.map(str::to_owned),
            waits,
            turn: turn.clone(),
        };
        self.lock().insert(arrival, waiter);
        Place { board: self.clone(), arrival, turn }
    }

    /// Everyone in line who waits for a task, but the holder of `place`, first come first.
    /// Nobody steps aside for an instant claim: it would leave with nothing, and the task it
    /// was left would wait for the next claim.
    pub fn others(&self, place: &Place) -> Vec<Waiter> {
        self.lock().values().filter(|w| w.waits && w.arrival != place.arrival).cloned().collect()
    }

    /// Notes that a robot passed over a task for another in line.
    pub fn stepped_aside(&self) {
        self.stepped_aside.store(true, Ordering::Release);
    }

    /// Robots waiting now.
    pub fn waiting(&self) -> usize {
        self.lock().len()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, BTreeMap<u64, Waiter>> {
        self.line.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A robot's place in line. Leaving it (with a task or without) passes the turn on, or gives
/// it back to the front of the line when a robot stepped aside for one ranked before it.
#[derive(Debug)]
pub struct Place {
    board: Arc<TaskBoard>,
    arrival: u64,
    turn: Arc<Notify>,
}

impl Place {
    pub fn arrival(&self) -> u64 {
        self.arrival
    }

    /// Completes when it is this robot's turn to look (at once if it was given meanwhile).
    pub async fn turn(&self) {
        self.turn.notified().await;
    }
}

impl Drop for Place {
    fn drop(&mut self) {
        if self.board.stepped_aside.swap(false, Ordering::AcqRel) {
            self.board.lock().remove(&self.arrival);
            self.board.changed();
        } else {
            self.board.pass_on(self);
            self.board.lock().remove(&self.arrival);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `place` has been given its turn (without waiting for it).
    fn has_turn(place: &Place) -> bool {
        let turn = std::pin::pin!(place.turn());
        let waker = std::task::Waker::noop();
        turn.poll(&mut std::task::Context::from_waker(waker)).is_ready()
    }

    use std::future::Future;

    fn robot(id: &str) -> RobotId {
        RobotId::parse(id).unwrap()
    }

    #[test]
    fn a_change_wakes_the_first_in_line_who_passes_the_turn_back() {
        let board = Arc::new(TaskBoard::default());
        let first = board.join(&robot("a"), Some("el-e"), true);
        let second = board.join(&robot("b"), None, true);
        let third = board.join(&robot("c"), None, true);
        let instant = board.join(&robot("d"), None, false);
        let others: Vec<String> =
            board.others(&second).into_iter().map(|w| w.robot.to_string()).collect();
        assert_eq!(others, ["a", "c"], "nobody steps aside for an instant claim");
        drop(instant);
        board.changed();
        assert!(has_turn(&first));
        assert!(!has_turn(&second) && !has_turn(&third), "one look per change");
        board.pass_on(&first);
        assert!(has_turn(&second));
        drop(second);
        assert!(has_turn(&third), "leaving the line passes the turn on");
        assert_eq!(board.waiting(), 2);
        board.stepped_aside();
        drop(third);
        assert!(has_turn(&first), "after stepping aside, the front looks again");
        drop(first);
        assert_eq!(board.waiting(), 0);
    }

    #[test]
    fn short_leases_are_swept_often_long_ones_every_second() {
        assert_eq!(
            TaskBoard::new(Duration::from_secs(2)).sweep_every(),
            Duration::from_millis(500)
        );
        assert_eq!(TaskBoard::default().sweep_every(), Duration::from_secs(1));
        assert_eq!(
            TaskBoard::new(Duration::from_millis(100)).sweep_every(),
            Duration::from_millis(50)
        );
    }
}
