//! What the registry keeps in memory about robots between requests: when each was last seen,
//! the unknown EPCs they read, and the line of those waiting for a task.

pub mod presence;
pub mod sightings;
pub mod waiting_line;
