//! llrpkit's LLRP reader emulator (PyPI `llrpkit`, MIT), run by `emulate.py` beside this file
//! with the tag population a test gives, and steered through its stdin.
//!
//! The emulator lives in the virtualenv `tests/run` makes (`target/llrpkit-venv`); set
//! `LLRPKIT_PYTHON` to use another interpreter that has llrpkit.

#![allow(dead_code)]

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use serde_json::{Value, json};

pub struct Emulator {
    pub port: u16,
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
}

/// One tag of the population: EPC (hex), the antennas that see it and how strongly.
pub fn tag(epc: &str, antennas: &[u16], rssi_dbm: f64) -> Value {
    json!({"epc": epc, "antennas": antennas, "rssi_dbm": rssi_dbm})
}

fn python() -> PathBuf {
    if let Some(python) = std::env::var_os("LLRPKIT_PYTHON") {
        return python.into();
    }
    let venv = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/llrpkit-venv/bin/python");
    assert!(
        venv.exists(),
        "llrpkit is not installed: run tests/llrpkit/install (tests/run does), or set \
         LLRPKIT_PYTHON to a Python that has llrpkit"
    );
    venv
}

impl Emulator {
    /// An emulator reading `tags` at `reads_per_sec`, listening on a free port of 127.0.0.1.
    pub fn start(tags: Vec<Value>, reads_per_sec: f64) -> Self {
        let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/llrpkit/emulate.py");
        let config = json!({"tags": tags, "reads_per_sec": reads_per_sec, "antenna_count": 4});
        let mut child = Command::new(python())
            .arg(script)
            .arg(config.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("the emulator starts");
        let stdin = child.stdin.take().expect("piped");
        let mut stdout = BufReader::new(child.stdout.take().expect("piped"));
        let mut line = String::new();
        stdout.read_line(&mut line).expect("the emulator names its port");
        let port = line
            .trim()
            .strip_prefix("port ")
            .and_then(|p| p.parse().ok())
            .unwrap_or_else(|| panic!("the emulator said `{line}` instead of its port"));
        Self { port, child, stdin, stdout }
    }

    pub fn address(&self) -> String {
        format!("127.0.0.1:{}", self.port)
    }

    /// One command to the emulator (see emulate.py) and its one-line answer.
    pub fn command(&mut self, command: &str) -> String {
        writeln!(self.stdin, "{command}").expect("the emulator is running");
        let mut line = String::new();
        self.stdout.read_line(&mut line).expect("the emulator answers");
        line.trim().to_owned()
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
