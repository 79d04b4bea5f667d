//! A simulated robot at work: a real `pps-robot work` process claiming the registry's tasks.

use std::process::{Child, Command, Stdio};

use tempfile::TempDir;

use crate::process::Registry;
use crate::workspace::workspace_bin;

/// A `pps-robot work` process and its state directory, ended when dropped.
#[derive(Debug)]
pub struct WorkingRobot {
    child: Child,
    _state: TempDir,
}

impl WorkingRobot {
    /// Starts `pps-robot work` as `robot` with its robot `token`; it ends by itself after two
    /// idle minutes should the test forget it.
    pub fn start(registry: &Registry, robot: &str, token: &str) -> Self {
        let state = tempfile::tempdir().expect("a state directory");
        let child = Command::new(workspace_bin("pps-robot"))
            .args(["work", "--server", &registry.url, "--robot", robot, "--idle-exit", "120"])
            .arg("--state")
            .arg(state.path())
            .env("PPS_TOKEN", token)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("pps-robot work starts");
        Self { child, _state: state }
    }
}

impl Drop for WorkingRobot {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
