//! Whether this process's Home Assistant bridge is connected, and if not why, for the admin page.

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Mutex, OnceLock};

/// The bridge as this process sees it; the API answers it by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
#[schemars(rename = "bridge_state")]
pub enum Status {
    /// No `--mqtt` was given.
    Off,
    /// Another replica holds the bridge's lease.
    Standby,
    /// This process runs the bridge and is (re)connecting to the broker.
    Connecting,
    /// This process runs the bridge and the broker answers.
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
pub struct BridgeStatus {
    status: AtomicU8,
    /// The broker (without its password) and the discovery prefix, once the bridge started.
    broker: OnceLock<(String, String)>,
    /// Why the bridge cannot use the broker now, in words; none while connected.
    problem: Mutex<Option<String>>,
}

impl BridgeStatus {
    /// The bridge is now `status`; only [`Status::Connecting`] keeps the problem said last.
    pub fn set(&self, status: Status) {
        self.status.store(status as u8, Ordering::Relaxed);
        if status != Status::Connecting {
            *self.problem_slot() = None;
        }
    }

    /// The bridge is (re)connecting because of `problem`.
    pub fn trouble(&self, problem: String) {
        self.set(Status::Connecting);
        *self.problem_slot() = Some(problem);
    }

    /// Why the bridge cannot use the broker now.
    pub fn problem(&self) -> Option<String> {
        self.problem_slot().clone()
    }

    fn problem_slot(&self) -> std::sync::MutexGuard<'_, Option<String>> {
        self.problem.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Notes where the bridge announces (once: the flags do not change while serving).
    pub fn configured(&self, broker: String, prefix: String) {
        let _ = self.broker.set((broker, prefix));
    }

    /// The broker and the discovery prefix, when the bridge is configured.
    pub fn broker(&self) -> Option<&(String, String)> {
        self.broker.get()
    }

    pub fn get(&self) -> Status {
        match self.status.load(Ordering::Relaxed) {
            1 => Status::Standby,
            2 => Status::Connecting,
            3 => Status::Connected,
            _ => Status::Off,
        }
    }
}
