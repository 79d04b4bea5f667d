//! Where the robot's programs say what they are doing: `tracing` on stderr, so a robot's own
//! logging stack (journald, a ROS 2 launch file, a test's captured stderr) receives it all.
//!
//! The default shows the client's progress and every warning; `RUST_LOG` chooses otherwise
//! (`RUST_LOG=pps_robot=debug` adds each missed trial's full report and the readers' traffic).

use std::io::IsTerminal;

use tracing_subscriber::EnvFilter;

/// The filter when `RUST_LOG` is unset: our own progress, everyone's warnings.
const DEFAULT_FILTER: &str = "warn,pps_robot=info";

/// Installs the stderr subscriber; call once, first thing in `main`.
pub fn init_logging() {
    let filter =
        EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(DEFAULT_FILTER));
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_env_filter(filter)
        .with_target(false)
        // Colours only for a person at a terminal, never into a log file or a test's capture.
        .with_ansi(std::io::stderr().is_terminal())
        .init();
}
