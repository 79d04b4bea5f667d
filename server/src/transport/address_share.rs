//! Each client address's share of the connections, so one host (a hostile one, or a robot
//! gone haywire) that opens and stalls connections cannot take every slot from the others.
//!
//! While fewer than half of the connections are in use, any address may open more than its
//! share: a quiet server lets a test rig or a burst of requests through. Once half are in use,
//! no address gets a connection beyond its small share, so whatever a few hosts grabbed early,
//! every other host still finds room.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::{Arc, Mutex};

/// Connections open per client address.
#[derive(Debug)]
pub struct AddressShares {
    share: usize,
    /// Connections in use from which every address is held to its share.
    crowded: usize,
    open: Mutex<Open>,
}

#[derive(Debug, Default)]
struct Open {
    by_address: HashMap<IpAddr, usize>,
    total: usize,
}

/// One connection counted against its address until dropped.
#[derive(Debug)]
pub struct AddressSlot {
    shares: Arc<AddressShares>,
    address: IpAddr,
}

impl AddressShares {
    /// Shares of `share` connections per address out of `max_connections`.
    pub fn new(share: usize, max_connections: usize) -> Arc<Self> {
        Arc::new(Self { share: share.max(1), crowded: max_connections / 2, open: Mutex::default() })
    }

    /// A slot for one more connection from `address`; `None` when it holds its share already
    /// and half of the connections are in use.
    pub fn claim(self: &Arc<Self>, address: IpAddr) -> Option<AddressSlot> {
        let mut open = self.open.lock().unwrap_or_else(|e| e.into_inner());
        let crowded = open.total >= self.crowded;
        let count = open.by_address.entry(address).or_insert(0);
        if *count >= self.share && crowded {
            return None;
        }
        *count += 1;
        open.total += 1;
        Some(AddressSlot { shares: self.clone(), address })
    }
}

impl Drop for AddressSlot {
    fn drop(&mut self) {
        let mut open = self.shares.open.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(count) = open.by_address.get_mut(&self.address) {
            *count -= 1;
            if *count == 0 {
                open.by_address.remove(&self.address);
            }
            open.total -= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn host(n: u8) -> IpAddr {
        [10, 0, 0, n].into()
    }

    #[test]
    fn an_address_gets_its_share_and_no_more_once_half_are_in_use() {
        let shares = AddressShares::new(2, 4);
        let (a, b) = (host(1), host(2));
        let first = shares.claim(a).unwrap();
        let _second = shares.claim(a).unwrap();
        assert!(shares.claim(a).is_none(), "half are in use, and a holds its share");
        assert!(shares.claim(b).is_some(), "another address has its own share");
        drop(first);
        assert!(shares.claim(a).is_some(), "a closed connection frees its place");
    }

    #[test]
    fn a_quiet_server_lets_one_address_open_up_to_half_and_every_other_address_its_share() {
        let shares = AddressShares::new(16, 512);
        let early: Vec<_> = (0..300).map_while(|_| shares.claim(host(1))).collect();
        assert_eq!(early.len(), 256);
        let second: Vec<_> = (0..300).map_while(|_| shares.claim(host(2))).collect();
        assert_eq!(second.len(), 16);
        // Any number of latecomers each find their share while room lasts.
        for n in 3..=17 {
            let latecomer: Vec<_> = (0..20).map_while(|_| shares.claim(host(n))).collect();
            assert_eq!(latecomer.len(), 16, "host {n}");
            std::mem::forget(latecomer);
        }
    }
}
