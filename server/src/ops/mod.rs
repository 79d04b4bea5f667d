//! Running the registry as an operator sees it: backups, private files, metrics and logs.

pub mod backup;
pub mod metrics;
pub mod private_file;
pub mod telemetry;
