//! The robot's side of the registry: typed HTTP calls, a cache of effective entries that
//! keeps the robot working when the server is away, and a durable outbox of trials.
//!
//! The registry is reached only through [`RegistryClient`]; behaviours never see HTTP.

mod change_watch;
mod client;
#[cfg(test)]
mod client_tests;
mod entry_cache;
mod error;
#[cfg(test)]
mod flaky_registry;
mod outbox;
pub mod retry;
mod state_file;
mod task_queue;

pub use change_watch::ChangeWatch;
pub use client::{Fetched, FlushReport, RegistryClient, Source};
pub use entry_cache::EntryCache;
pub use error::{Problem, RegistryError};
pub use outbox::{PendingTrial, TrialOutbox};
pub use task_queue::QueuedTask;
