//! The registry's SQL, one module per resource, and the database it runs on (`db`: opening,
//! migrating, the engines' differences). Nothing above this layer writes SQL.

pub mod backup;
pub mod columns;
pub mod db;
pub mod events;
pub mod home_assistant;
pub mod inbox;
pub mod learned_colours;
pub mod learned_sizes;
pub mod learning;
pub mod pictures;
pub mod placeholders;
pub mod retired;
pub mod robots;
pub mod sessions;
pub mod tags;
pub mod tasks;
pub mod tokens;
pub mod trial_counts;
pub mod trials;
pub mod users;
mod write_condition;

pub use write_condition::WriteCondition;
