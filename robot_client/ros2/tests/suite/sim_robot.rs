//! The `sim_robot` example as a person runs it: it says how it stops, and with `--clicks N` it
//! does, by itself, after N clicks.

use std::path::PathBuf;
use std::process::Command;

use crate::support::netns;

/// The example next to this test binary (`target/<profile>/examples/`).
fn example() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile = exe.parent().unwrap().parent().unwrap();
    profile.join("examples").join("sim_robot")
}

#[test]
fn sim_robot_stops_after_the_clicks_it_was_asked_for() {
    if !netns::isolated("sim_robot::sim_robot_stops_after_the_clicks_it_was_asked_for") {
        return;
    }
    let output = Command::new(example())
        .args(["--clicks", "2", "--every", "0.2", "--dds-interface", "127.0.0.1"])
        .output()
        .expect("the sim_robot example was built with the tests");
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{said}");
    assert!(said.contains("stops after 2 clicks, or press Ctrl-C"), "{said}");
    assert!(said.trim_end().ends_with("sent 2 clicks; stopping"), "{said}");
}
