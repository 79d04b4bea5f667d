//! A real Mosquitto broker (Debian's `mosquitto`) for the Home Assistant bridge's tests: on
//! 127.0.0.1 only, its configuration in a temporary directory, retained messages kept in
//! memory only (so a restart loses them, as a broker's crash can).

use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use tempfile::TempDir;

use pps_test_kit::wait;

/// A running broker; stopped when dropped.
#[derive(Debug)]
pub struct Mosquitto {
    child: Option<Child>,
    pub port: u16,
    config: PathBuf,
    _dir: TempDir,
}

impl Mosquitto {
    /// Starts a broker on a free loopback port and waits until it takes connections.
    pub async fn start() -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let port = TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
            .and_then(|listener| listener.local_addr())
            .expect("a free loopback port")
            .port();
        let config = dir.path().join("mosquitto.conf");
        std::fs::write(
            &config,
            format!(
                "listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\nsys_interval 1\n\
                 log_dest none\n"
            ),
        )
        .expect("the broker's configuration is written");
        let mut broker = Self { child: None, port, config, _dir: dir };
        broker.restart().await;
        broker
    }

    /// The URL `serve --mqtt` takes.
    pub fn url(&self) -> String {
        format!("mqtt://127.0.0.1:{}", self.port)
    }

    /// Kills the broker at once, as a crash would: no goodbye to its clients.
    pub fn kill(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    /// Starts the broker (again) on the same port and waits until it takes connections.
    pub async fn restart(&mut self) {
        self.kill();
        let child = Command::new(mosquitto_bin())
            .arg("-c")
            .arg(&self.config)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("mosquitto starts");
        self.child = Some(child);
        let port = self.port;
        wait::until("mosquitto to take connections", || async move {
            TcpStream::connect((Ipv4Addr::LOCALHOST, port)).ok().map(drop)
        })
        .await;
    }
}

impl Drop for Mosquitto {
    fn drop(&mut self) {
        self.kill();
    }
}

/// Debian installs the broker in /usr/sbin, which a user's PATH may lack.
fn mosquitto_bin() -> PathBuf {
    let installed = PathBuf::from("/usr/sbin/mosquitto");
    if installed.is_file() {
        return installed;
    }
    let on_path = std::env::var_os("PATH")
        .into_iter()
        .flat_map(|path| std::env::split_paths(&path).collect::<Vec<_>>())
        .map(|dir| dir.join("mosquitto"))
        .find(|candidate| candidate.is_file());
    on_path.unwrap_or_else(|| {
        panic!("mosquitto is missing: install Debian's mosquitto package (tests/run does)")
    })
}
