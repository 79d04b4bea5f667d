//! The registry's tests, one binary: each module was a test file of its own (linking one binary
//! for each cost more than running them). nextest still runs each test in a process of its
//! own; the test command runs `replicas` (PostgreSQL's) by its path, `replicas::`.

mod access_table;
mod auth;
mod bridge_lease;
mod cli;
mod effective_entries;
mod feed_and_metrics;
mod http_errors;
mod learned_colour;
mod learned_size;
mod learning;
mod limits;
mod openapi;
mod ops;
mod replicas;
mod tag_lifecycle;
mod tags_api;
mod task_queue;
mod tasks_api;
mod transport;
mod trial_pictures;
mod trial_purpose;
mod trials_api;
mod users_sessions;
