//! The network rule for tests: DDS runs only inside a fresh network namespace that has nothing
//! but loopback. A test calls [`isolated`] first; outside such a namespace it re-runs itself
//! inside one (`unshare --net`, root) and reports how that went, and never speaks DDS here.

#![allow(dead_code)]

use std::process::Command;

/// Set in the re-run's environment; the namespace is still checked, never trusted.
const MARKER: &str = "PPS_ROS2_TEST_NETNS";

/// Network interfaces of this process's network namespace (`/proc/self/net/dev` is per
/// namespace; `/sys/class/net` shows the namespace that mounted sysfs).
fn interfaces() -> Vec<String> {
    std::fs::read_to_string("/proc/self/net/dev")
        .unwrap_or_default()
        .lines()
        .skip(2)
        .filter_map(|line| Some(line.split_once(':')?.0.trim().to_owned()))
        .collect()
}

/// Whether this process is the re-run inside the loopback-only namespace; panics when it claims
/// to be but can see other interfaces.
pub fn inside() -> bool {
    if std::env::var_os(MARKER).is_none() {
        return false;
    }
    let seen = interfaces();
    assert!(
        seen.iter().all(|i| i == "lo"),
        "refusing to run DDS: this namespace has interfaces besides loopback: {seen:?}"
    );
    true
}

/// Runs this binary again with `args` inside a fresh network namespace with only loopback
/// (multicast on, 224.0.0.0/4 routed to it), and returns its output.
pub fn rerun_inside(args: &[&str]) -> std::process::Output {
    let exe = std::env::current_exe().expect("the binary knows its path");
    Command::new("unshare")
        .args(["--net", "bash", "-c"])
        .arg(
            "set -e; ip link set lo up; ip link set lo multicast on; \
             ip route add 224.0.0.0/4 dev lo; exec \"$0\" \"$@\"",
        )
        .arg(&exe)
        .args(args)
        .env(MARKER, "1")
        .output()
        .unwrap_or_else(|e| panic!("cannot run `unshare` to isolate DDS from the network: {e}"))
}

/// `true` inside the loopback-only namespace: go on with DDS. `false` when this process re-ran
/// `test` inside one and it passed: the caller returns at once. Panics when the re-run failed
/// or no namespace could be made.
pub fn isolated(test: &str) -> bool {
    if inside() {
        return true;
    }
    let output = rerun_inside(&[test, "--exact", "--nocapture", "--test-threads=1"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "{test} inside a loopback-only network namespace failed ({}); it needs root for \
         `unshare --net` and `ip`.\n--- stdout\n{stdout}\n--- stderr\n{stderr}",
        output.status
    );
    assert!(
        stdout.contains("1 passed"),
        "{test} did not run inside the namespace:\n{stdout}\n{stderr}"
    );
    false
}

/// Cyclone DDS on loopback, multicast included: what the peer needs inside the namespace.
pub const CYCLONEDDS_LOOPBACK: &str = "<CycloneDDS><Domain><General><Interfaces>\
    <NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces></General>\
    <Internal><SocketReceiveBufferSize min=\"1MB\"/></Internal></Domain></CycloneDDS>";
