//! What the workspace's build left for the tests: the Cargo target directory and the binaries
//! in it, found from the test binary's own path so that any profile and target dir work.

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
