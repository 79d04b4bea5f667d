//! TLS to the broker for rumqttc. rumqttc 0.25 speaks TLS only through its own rustls feature,
//! which brings a second rustls-webpki beside the workspace's, and it takes no stream made
//! elsewhere; but it connects to a Unix socket when told to. So the bridge gives it one: a
//! socket in a directory of its own that only this process's user can enter, and every
//! connection made to it is carried to the broker over TLS made with the workspace's rustls
//! ([`BrokerTrust`]). MQTT itself (session, keep-alive, last will) stays rumqttc's.
//!
//! A handshake that fails closes rumqttc's side at once; the sentence saying why is kept for
//! the connection to report in place of rumqttc's "connection closed".

use std::io;
use std::os::unix::fs::PermissionsExt;
use std::sync::{Arc, Mutex};

use tempfile::TempDir;
use tokio::net::{UnixListener, UnixStream};
use tokio::task::JoinHandle;

use super::Broker;
use super::trust::BrokerTrust;

/// Why the last connection could not be carried, until the connection reads it.
type Failure = Arc<Mutex<Option<String>>>;

/// A private socket whose connections go on to the broker over TLS; closed when dropped.
pub struct TlsRelay {
    socket: String,
    failure: Failure,
    accepting: JoinHandle<()>,
    _dir: TempDir,
}

impl TlsRelay {
    /// Opens the socket and starts carrying its connections to `broker`.
    pub fn start(broker: &Broker, trust: &BrokerTrust) -> io::Result<Self> {
        // Only this user may enter the directory, so only this user can reach the socket.
        let dir = tempfile::Builder::new()
            .prefix("pps-mqtts-")
            .permissions(std::fs::Permissions::from_mode(0o700))
            .tempdir()?;
        let path = dir.path().join("broker.sock");
        let socket = path
            .to_str()
            .ok_or_else(|| {
                io::Error::other(format!("the temporary directory {} is not UTF-8", path.display()))
            })?
            .to_owned();
        let listener = UnixListener::bind(&path)?;
        let failure = Failure::default();
        let accepting =
            tokio::spawn(accept(listener, broker.clone(), trust.clone(), failure.clone()));
        Ok(Self { socket, failure, accepting, _dir: dir })
    }

    /// Where rumqttc connects.
    pub fn socket(&self) -> &str {
        &self.socket
    }

    /// Why the last connection was closed before reaching the broker, once.
    pub fn take_failure(&self) -> Option<String> {
        self.failure.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).take()
    }
}

impl Drop for TlsRelay {
    fn drop(&mut self) {
        self.accepting.abort();
    }
}

/// Accepts rumqttc's connections, each carried on in a task of its own.
async fn accept(listener: UnixListener, broker: Broker, trust: BrokerTrust, failure: Failure) {
    loop {
        match listener.accept().await {
            Ok((local, _)) => {
                tokio::spawn(carry(local, broker.clone(), trust.clone(), failure.clone()));
            }
            Err(error) => {
                tracing::warn!(%error, "the bridge's TLS socket stopped taking connections");
                return;
            }
        }
    }
}

/// Connects to the broker over TLS and copies both ways until either side closes.
async fn carry(mut local: UnixStream, broker: Broker, trust: BrokerTrust, failure: Failure) {
    match trust.connect(&broker).await {
        Ok(mut remote) => {
            // Either side closing ends the connection; rumqttc notices and reconnects.
            let _ = tokio::io::copy_bidirectional(&mut local, &mut remote).await;
        }
        Err(why) => {
            // Kept before rumqttc's side closes (when `local` drops), so it is there to read.
            *failure.lock().unwrap_or_else(|poisoned| poisoned.into_inner()) = Some(why);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use tokio::io::AsyncReadExt;

    use super::*;

    /// Trust in a CA made for the test (no broker here gets that far).
    fn trust(dir: &Path) -> BrokerTrust {
        let ca = rcgen::generate_simple_self_signed(vec!["ca.test".to_owned()]).unwrap();
        let file = dir.join("ca.pem");
        std::fs::write(&file, ca.cert.pem()).unwrap();
        BrokerTrust::ca_file(&file).unwrap()
    }

    #[tokio::test]
    async fn the_socket_is_private_and_gone_when_dropped() {
        let files = tempfile::tempdir().unwrap();
        let broker: Broker = "mqtts://127.0.0.1:9".parse().unwrap();
        let relay = TlsRelay::start(&broker, &trust(files.path())).unwrap();
        let dir = Path::new(relay.socket()).parent().unwrap().to_owned();
        let mode = std::fs::metadata(&dir).unwrap().permissions().mode();
        assert_eq!(mode & 0o077, 0, "the socket's directory is open to others: {mode:o}");
        drop(relay);
        assert!(!dir.exists(), "the socket's directory outlived the relay");
    }

    #[tokio::test]
    async fn a_failed_handshake_closes_the_socket_and_says_why() {
        let files = tempfile::tempdir().unwrap();
        // A "broker" that hangs up on every greeting, as a plain MQTT broker does.
        let hangs_up = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let port = hangs_up.local_addr().unwrap().port();
        tokio::spawn(async move {
            while let Ok((mut stream, _)) = hangs_up.accept().await {
                // The whole greeting read first: closing on unread bytes would reset instead.
                let mut header = [0; 5];
                stream.read_exact(&mut header).await.unwrap();
                let mut hello = vec![0; usize::from(u16::from_be_bytes([header[3], header[4]]))];
                stream.read_exact(&mut hello).await.unwrap();
            }
        });
        let broker: Broker = format!("mqtts://127.0.0.1:{port}").parse().unwrap();
        let relay = TlsRelay::start(&broker, &trust(files.path())).unwrap();
        let mut local = UnixStream::connect(relay.socket()).await.unwrap();
        let mut read = Vec::new();
        local.read_to_end(&mut read).await.unwrap();
        assert!(read.is_empty());
        let why = relay.take_failure().expect("the reason is kept");
        assert_eq!(
            why,
            format!(
                "the MQTT broker at mqtts://127.0.0.1:{port} does not speak TLS on port {port}: \
                 use mqtt://127.0.0.1:{port} if that port is plain MQTT, or the broker's TLS \
                 port (usually 8883)"
            )
        );
        assert_eq!(relay.take_failure(), None, "said once");
    }
}
