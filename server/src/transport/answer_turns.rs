//! Turns at building heavy answers (megabytes of trial history), fair between client
//! addresses, so that hosts asking for many of them at once cannot take every core from
//! everyone else.
//!
//! Each address builds one heavy answer at a time: its further requests queue behind each
//! other, on whatever connections they came. Across addresses, at most `at_once` answers are
//! built together, one core fewer than the machine has (at least one), so a core is always
//! left for light requests. The turns go round the addresses that wait, in the order they
//! came, so any number of hosts each get their share and none is starved of its own answers.
//! Requests that are not heavy never wait here.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use tokio::sync::{OwnedSemaphorePermit, Semaphore};

/// Who is building a heavy answer and who waits to.
#[derive(Debug)]
pub struct AnswerTurns {
    /// Answers built at once, across addresses. Tokio's semaphore is first come, first
    /// served, and each address has at most one request waiting on it, so its queue goes
    /// round the addresses.
    building: Arc<Semaphore>,
    at_once: usize,
    /// One turn per address; an entry lives while anyone from the address holds or waits for
    /// a turn.
    addresses: Mutex<HashMap<IpAddr, Arc<Semaphore>>>,
    waiting: AtomicUsize,
}

/// The right to build one heavy answer, until dropped.
#[derive(Debug)]
pub struct Turn {
    // Fields drop in order: the permits before the address's entry is looked at.
    _building: OwnedSemaphorePermit,
    _address: OwnedSemaphorePermit,
    _queue: AddressQueue,
}

impl AnswerTurns {
    /// Turns for `at_once` heavy answers at a time (at least one).
    pub fn new(at_once: usize) -> Self {
        let at_once = at_once.max(1);
        Self {
            building: Arc::new(Semaphore::new(at_once)),
            at_once,
            addresses: Mutex::default(),
            waiting: AtomicUsize::new(0),
        }
    }

    /// Turns for one core fewer than this machine has, at least one.
    pub fn for_this_machine() -> Self {
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        Self::new(cores - 1)
    }

    /// Waits for `address`'s turn to build a heavy answer.
    pub async fn turn(self: &Arc<Self>, address: IpAddr) -> Turn {
        let queue = AddressQueue::join(self, address);
        let _waiting = Waiting::count(&self.waiting);
        let semaphore = queue.semaphore();
        let address_turn = semaphore.acquire_owned().await.expect("never closed");
        let building = self.building.clone().acquire_owned().await.expect("never closed");
        Turn { _building: building, _address: address_turn, _queue: queue }
    }

    /// Requests waiting for their turn.
    pub fn waiting(&self) -> usize {
        self.waiting.load(Ordering::Relaxed)
    }

    /// Heavy answers being built.
    pub fn building(&self) -> usize {
        self.at_once - self.building.available_permits()
    }
}

/// A request's place in its address's queue: keeps the address's entry alive and removes it
/// when the last request from the address is done or gone.
#[derive(Debug)]
struct AddressQueue {
    turns: Arc<AnswerTurns>,
    address: IpAddr,
    semaphore: Option<Arc<Semaphore>>,
}

impl AddressQueue {
    fn join(turns: &Arc<AnswerTurns>, address: IpAddr) -> Self {
        let mut addresses = turns.addresses.lock().unwrap_or_else(|e| e.into_inner());
        let semaphore = addresses.entry(address).or_insert_with(|| Arc::new(Semaphore::new(1)));
        Self { turns: turns.clone(), address, semaphore: Some(semaphore.clone()) }
    }

    fn semaphore(&self) -> Arc<Semaphore> {
        self.semaphore.clone().expect("present until dropped")
    }
}

impl Drop for AddressQueue {
    fn drop(&mut self) {
        let mut addresses = self.turns.addresses.lock().unwrap_or_else(|e| e.into_inner());
        // Every clone is made or dropped with its queue entry, and the permits (which hold
        // clones too) are gone before it: the map's own reference alone means nobody is left.
        drop(self.semaphore.take());
        if addresses.get(&self.address).is_some_and(|s| Arc::strong_count(s) == 1) {
            addresses.remove(&self.address);
        }
    }
}

/// Counts a request as waiting until its turn comes or it is given up.
struct Waiting<'a>(&'a AtomicUsize);

impl<'a> Waiting<'a> {
    fn count(waiting: &'a AtomicUsize) -> Self {
        waiting.fetch_add(1, Ordering::Relaxed);
        Self(waiting)
    }
}

impl Drop for Waiting<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use std::future::Future;
    use std::pin::Pin;

    use futures_util::FutureExt;

    use super::*;

    fn host(n: u8) -> IpAddr {
        [10, 0, 0, n].into()
    }

    type Asking = Pin<Box<dyn Future<Output = Turn>>>;

    fn ask(turns: &Arc<AnswerTurns>, address: IpAddr) -> Asking {
        let turns = turns.clone();
        Box::pin(async move { turns.turn(address).await })
    }

    /// Polls each request once, in order, so each joins its queues in that order.
    fn queue_up(asking: &mut [&mut Asking]) {
        for request in asking {
            assert!(request.as_mut().now_or_never().is_none());
        }
    }

    #[tokio::test]
    async fn turns_go_round_the_addresses_so_a_latecomer_is_served_before_a_host_s_backlog() {
        let turns = Arc::new(AnswerTurns::new(1));
        let first = turns.turn(host(1)).await;
        let (mut a2, mut a3, mut a4) =
            (ask(&turns, host(1)), ask(&turns, host(1)), ask(&turns, host(1)));
        let mut b1 = ask(&turns, host(2));
        let mut c1 = ask(&turns, host(3));
        queue_up(&mut [&mut a2, &mut a3, &mut a4, &mut b1, &mut c1]);
        assert_eq!((turns.building(), turns.waiting()), (1, 5));

        let mut served = Vec::new();
        let mut current = first;
        let mut asking = vec![("a2", a2), ("a3", a3), ("a4", a4), ("b1", b1), ("c1", c1)];
        while !asking.is_empty() {
            drop(current);
            let mut ready = None;
            for (n, (name, request)) in asking.iter_mut().enumerate() {
                if let Some(turn) = request.as_mut().now_or_never() {
                    assert!(ready.is_none(), "one turn at a time");
                    ready = Some((n, *name, turn));
                }
            }
            let (n, name, turn) = ready.expect("a turn was freed");
            served.push(name);
            drop(asking.remove(n));
            current = turn;
        }
        assert_eq!(served, ["b1", "c1", "a2", "a3", "a4"]);
        drop(current);
        assert_eq!((turns.building(), turns.waiting()), (0, 0));
        assert!(turns.addresses.lock().unwrap().is_empty(), "no address is remembered");
    }

    #[tokio::test]
    async fn each_address_builds_one_answer_at_a_time_and_others_use_the_rest() {
        let turns = Arc::new(AnswerTurns::new(2));
        let _a1 = turns.turn(host(1)).await;
        let mut a2 = ask(&turns, host(1));
        queue_up(&mut [&mut a2]);
        let _b1 = turns.turn(host(2)).await;
        assert_eq!((turns.building(), turns.waiting()), (2, 1));
    }

    #[tokio::test]
    async fn a_request_given_up_while_waiting_leaves_nothing_behind() {
        let turns = Arc::new(AnswerTurns::new(1));
        let held = turns.turn(host(1)).await;
        let mut gone = ask(&turns, host(2));
        let mut also_gone = ask(&turns, host(1));
        queue_up(&mut [&mut gone, &mut also_gone]);
        drop((gone, also_gone));
        assert_eq!(turns.waiting(), 0);
        drop(held);
        assert!(turns.addresses.lock().unwrap().is_empty());
        let _next = turns.turn(host(3)).await;
        assert_eq!(turns.building(), 1);
    }
}
