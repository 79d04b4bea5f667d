//! `pps-robot work`'s flags as a person gives them: out-of-range durations end in a sentence
//! before anything connects.

use std::process::Command;

#[test]
fn an_idle_exit_beyond_a_week_is_refused_with_the_range() {
    let dir = tempfile::tempdir().unwrap();
    for wrong in ["1e300", "604801", "-1", "NaN"] {
        let output = Command::new(env!("CARGO_BIN_EXE_pps-robot"))
            .args(["work", "--server", "http://127.0.0.1:9", "--token", "t", "--robot", "r"])
            .arg("--state")
            .arg(dir.path())
            .arg(format!("--idle-exit={wrong}"))
            .output()
            .unwrap();
        let said = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{wrong}: {said}");
        assert!(said.contains("--idle-exit takes 0 to 604800 seconds (a week)"), "{wrong}: {said}");
        assert!(!said.contains("panicked"), "{wrong}: {said}");
    }
}
