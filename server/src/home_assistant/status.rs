//! Whether this process's bridge is connected, for the admin page.

use std::sync::atomic::{AtomicU8, Ordering};

/// The bridge as this process sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// No `--mqtt` was given.
    Off,
    /// Another replica holds the bridge's lease.
    Standby,
    /// This process runs the bridge and is (re)connecting to the broker.
    Connecting,
    Connected,
}

impl Status {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::Standby => "standby",
            Self::Connecting => "connecting",
            Self::Connected => "connected",
        }
    }
}

/// The bridge's status, shared with the HTTP side.
#[derive(Debug, Default)]
pub struct BridgeStatus(AtomicU8);

impl BridgeStatus {
    pub fn set(&self, status: Status) {
        self.0.store(status as u8, Ordering::Relaxed);
    }

    pub fn get(&self) -> Status {
        match self.0.load(Ordering::Relaxed) {
            1 => Status::Standby,
            2 => Status::Connecting,
            3 => Status::Connected,
            _ => Status::Off,
        }
    }
}
