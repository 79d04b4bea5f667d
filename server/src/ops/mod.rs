//! Running the registry as an operator sees it: backups, metrics and logs, and whether the
//! Home Assistant bridge is connected.

pub mod backup;
pub mod bridge_status;
pub mod metrics;
pub mod telemetry;
