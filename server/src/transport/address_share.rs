//! Each client address's share of the connections, so one host (a hostile one, or a robot
//! gone haywire) that opens and stalls connections cannot take every slot from the others.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::{Arc, Mutex};

/// Connections open per client address.
#[derive(Debug)]
pub struct AddressShares {
    share: usize,
    open: Mutex<HashMap<IpAddr, usize>>,
}

/// One connection counted against its address until dropped.
#[derive(Debug)]
pub struct AddressSlot {
    shares: Arc<AddressShares>,
    address: IpAddr,
}

impl AddressShares {
    pub fn new(share: usize) -> Arc<Self> {
        Arc::new(Self { share: share.max(1), open: Mutex::default() })
    }

    /// A slot for one more connection from `address`; `None` when it holds its share already.
    pub fn claim(self: &Arc<Self>, address: IpAddr) -> Option<AddressSlot> {
        let mut open = self.open.lock().unwrap_or_else(|e| e.into_inner());
        let count = open.entry(address).or_insert(0);
        if *count >= self.share {
            return None;
        }
        *count += 1;
        Some(AddressSlot { shares: self.clone(), address })
    }
}

impl Drop for AddressSlot {
    fn drop(&mut self) {
        let mut open = self.shares.open.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(count) = open.get_mut(&self.address) {
            *count -= 1;
            if *count == 0 {
                open.remove(&self.address);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_address_gets_its_share_and_no_more() {
        let shares = AddressShares::new(2);
        let (a, b): (IpAddr, IpAddr) = ([10, 0, 0, 1].into(), [10, 0, 0, 2].into());
        let first = shares.claim(a).unwrap();
        let _second = shares.claim(a).unwrap();
        assert!(shares.claim(a).is_none());
        assert!(shares.claim(b).is_some(), "another address has its own share");
        drop(first);
        assert!(shares.claim(a).is_some(), "a closed connection frees its place");
    }
}
