//! A real Mosquitto broker (Debian's `mosquitto`) for the Home Assistant bridge's tests: on
//! 127.0.0.1 only, its configuration in a temporary directory, retained messages kept in
//! memory only (so a restart loses them, as a broker's crash can). It may also speak TLS on a
//! second port, with a certificate the test made; the plain port stays for the test's own
//! clients.

use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use tempfile::TempDir;

use crate::test_ca::ServerIdentity;
use pps_test_kit::wait;

/// A running broker; stopped when dropped.
#[derive(Debug)]
pub struct Mosquitto {
    child: Option<Child>,
    pub port: u16,
    /// The TLS listener's port, when the broker has one.
    pub tls_port: Option<u16>,
    config: PathBuf,
    dir: TempDir,
}

impl Mosquitto {
    /// Starts a broker on a free loopback port and waits until it takes connections.
    pub async fn start() -> Self {
        Self::start_with(None).await
    }

    /// Starts a broker that also speaks TLS as `identity` on a second loopback port.
    pub async fn start_tls(identity: &ServerIdentity) -> Self {
        Self::start_with(Some(identity)).await
    }

    async fn start_with(identity: Option<&ServerIdentity>) -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        // Both taken before either is let go, so that they differ.
        let [port, second_port] = free_ports();
        let config = dir.path().join("mosquitto.conf");
        let mut text = format!(
            "listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\nsys_interval 1\n\
             log_dest none\n"
        );
        let mut tls_port = None;
        if identity.is_some() {
            let port = second_port;
            let (cert, key) = (dir.path().join("broker.crt"), dir.path().join("broker.key"));
            text.push_str(&format!(
                "listener {port} 127.0.0.1\ncertfile {}\nkeyfile {}\n",
                cert.display(),
                key.display()
            ));
            tls_port = Some(port);
        }
        std::fs::write(&config, text).expect("the broker's configuration is written");
        let mut broker = Self { child: None, port, tls_port, config, dir };
        if let Some(identity) = identity {
            broker.set_identity(identity);
        }
        broker.restart().await;
        broker
    }

    /// Gives the TLS listener `identity`, from the next (re)start on.
    pub fn set_identity(&mut self, identity: &ServerIdentity) {
        let dir = self.dir.path();
        std::fs::write(dir.join("broker.crt"), &identity.cert_pem).expect("the certificate");
        std::fs::write(dir.join("broker.key"), &identity.key_pem).expect("the key");
    }

    /// The URL `serve --mqtt` takes for the TLS listener.
    pub fn tls_url(&self) -> String {
        format!("mqtts://127.0.0.1:{}", self.tls_port.expect("a broker started with TLS"))
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
        for port in [Some(self.port), self.tls_port].into_iter().flatten() {
            wait::until("mosquitto to take connections", || async move {
                TcpStream::connect((Ipv4Addr::LOCALHOST, port)).ok().map(drop)
            })
            .await;
        }
    }
}

impl Drop for Mosquitto {
    fn drop(&mut self) {
        self.kill();
    }
}

/// Loopback ports nobody listens on now, all different.
fn free_ports<const N: usize>() -> [u16; N] {
    let listeners: Vec<TcpListener> = (0..N)
        .map(|_| TcpListener::bind((Ipv4Addr::LOCALHOST, 0)).expect("a free loopback port"))
        .collect();
    std::array::from_fn(|i| listeners[i].local_addr().expect("a bound port").port())
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
