//! Shared harness for the end-to-end tests in `tests/tests/`: the real `pps-server` process on a
//! fresh database, and a real headless Chromium driven over WebDriver.
//!
//! Nothing here skips: when the server binary, Chromium or its driver is missing, the harness
//! panics and the test fails, saying what to install.

pub mod browser;
pub mod caretaker_view;
pub mod fixtures;
pub mod home_assistant;
pub mod module_graph;
pub mod mosquitto;
pub mod mqtt_watch;
pub mod registry;
pub mod test_ca;
pub mod wait;
pub mod working_robot;

pub use browser::{Browser, Session};
pub use home_assistant::HomeAssistant;
pub use mosquitto::Mosquitto;
pub use mqtt_watch::MqttWatch;
pub use registry::Registry;
pub use test_ca::{ServerIdentity, TestCa};
pub use working_robot::WorkingRobot;

use std::path::PathBuf;

/// The Cargo target directory this test binary was built into (`target/`).
pub fn target_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary knows its path");
    // target/<profile>/deps/<test binary>
    exe.ancestors().nth(3).expect("the test binary lives in target/<profile>/deps").to_path_buf()
}

/// A binary of the workspace, built next to this test binary (`tests/run` builds them first).
pub fn workspace_bin(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary knows its path");
    let path = exe.ancestors().nth(2).expect("target/<profile>").join(name);
    assert!(
        path.is_file(),
        "{} is missing: build the binaries first (`cargo build --workspace --bins`, as tests/run does)",
        path.display()
    );
    path
}
