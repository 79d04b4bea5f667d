//! The test kit every suite of the workspace shares: the registry in-process
//! ([`TestServer`]) and as the real process ([`Registry`]), what tests send to its API, the
//! change feed as a client reads it, robots at work ([`WorkingRobot`]), and waiting until a
//! condition holds ([`wait`]), never for a fixed time.
//!
//! Nothing here skips: when a binary or a PostgreSQL cluster a test needs is missing, the kit
//! panics and the test fails, saying what to do.

pub mod api;
pub mod fixtures;
pub mod in_process;
pub mod metrics;
pub mod postgres;
pub mod process;
#[cfg(feature = "robot")]
pub mod robots;
pub mod sse;
pub mod tasks;
pub mod wait;
pub mod working_robot;
pub mod workspace;

pub use api::{
    ADA_SWITCH, ALL, DRAWER, FLIP_SWITCH, LAMP, new_entry, pointers, problem, register_robot,
    trial, uuid,
};
pub use in_process::{Config, Store, TestServer, store_under_test};
pub use metrics::{Served, metric, robots_waiting};
pub use process::Registry;
#[cfg(feature = "robot")]
pub use robots::{EL_E, RobotRegistry};
pub use sse::{SseClient, SseEvent};
pub use tasks::{ask, asked, claim};
pub use wait::{wait_for, wait_until, wait_until_blocking};
pub use working_robot::WorkingRobot;
pub use workspace::{target_dir, workspace_bin};
