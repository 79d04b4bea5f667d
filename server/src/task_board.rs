//! The robots waiting for a task, in the order they asked, and the signal that wakes them.
//!
//! A claim that finds nothing waits in line here until a task is asked for, a lease runs out
//! or a robot ahead of it leaves the line (it may have passed over a task for that robot), so a
//! new task reaches a waiting robot at once instead of at its next poll. The line's order is
//! the fairness rule's tie-break: among robots equally suited, the one that asked first.
//! The board holds no task state: the database does, so a restart loses nothing but the line.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::watch;

/// How long a claim holds a task before it goes back to the queue, unless heartbeats extend it.
pub const DEFAULT_LEASE: Duration = Duration::from_secs(30);

/// One robot waiting in line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Waiter {
    /// Its place: lower asked earlier.
    pub arrival: u64,
    pub robot: String,
    pub class: Option<String>,
}

#[derive(Debug)]
pub struct TaskBoard {
    lease: Duration,
    changes: watch::Sender<u64>,
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
            changes: watch::Sender::new(0),
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

    /// Wakes every waiting robot: a task may be there for one of them.
    pub fn changed(&self) {
        self.changes.send_modify(|n| *n = n.wrapping_add(1));
    }

    /// The signal [`Self::changed`] raises.
    pub fn subscribe(&self) -> watch::Receiver<u64> {
        self.changes.subscribe()
    }

    /// Puts `robot` in line until the returned place is dropped.
    pub fn join(self: &Arc<Self>, robot: &str, class: Option<&str>) -> Place {
        let arrival = self.arrivals.fetch_add(1, Ordering::Relaxed);
        let waiter = Waiter { arrival, robot: robot.to_owned(), class: class.map(str::to_owned) };
        self.lock().insert(arrival, waiter);
        Place { board: self.clone(), arrival }
    }

    /// Everyone in line but the holder of `place`, first come first.
    pub fn others(&self, place: &Place) -> Vec<Waiter> {
        self.lock().values().filter(|w| w.arrival != place.arrival).cloned().collect()
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

/// A robot's place in line; leaving it (with a task or without) wakes the others when one of
/// them may have stepped aside for it.
#[derive(Debug)]
pub struct Place {
    board: Arc<TaskBoard>,
    arrival: u64,
}

impl Place {
    pub fn arrival(&self) -> u64 {
        self.arrival
    }
}

impl Drop for Place {
    fn drop(&mut self) {
        let removed = self.board.lock().remove(&self.arrival);
        if removed.is_some() && self.board.stepped_aside.swap(false, Ordering::AcqRel) {
            self.board.changed();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_keeps_arrival_order_and_leaving_wakes_the_rest() {
        let board = Arc::new(TaskBoard::default());
        let first = board.join("a", Some("el-e"));
        let second = board.join("b", None);
        let third = board.join("c", None);
        let others: Vec<String> = board.others(&second).into_iter().map(|w| w.robot).collect();
        assert_eq!(others, ["a", "c"]);
        let mut signal = board.subscribe();
        signal.borrow_and_update();
        drop(first);
        assert!(!signal.has_changed().unwrap(), "nobody stepped aside: nobody is woken");
        board.stepped_aside();
        let fourth = board.join("d", None);
        drop(fourth);
        assert!(signal.has_changed().unwrap(), "the others are woken");
        assert_eq!(board.waiting(), 2);
        drop((second, third));
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
