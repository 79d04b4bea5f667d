//! Whom the bridge believes when it speaks TLS to the broker (`mqtts://`): the system's CA
//! certificates, or only the CA that `--mqtt-ca` names, since home brokers mostly sign their
//! certificates with a CA of their own. The handshake is made here, with the workspace's
//! rustls, and what can go wrong in it is said in words a person can act on.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use anyhow::{Context, bail};
use rustls::pki_types::pem::PemObject;
use rustls::pki_types::{CertificateDer, ServerName};
use rustls::{CertificateError, RootCertStore};
use tokio::net::TcpStream;
use tokio_rustls::TlsConnector;
use tokio_rustls::client::TlsStream;

use super::Broker;

/// The TCP connection and the TLS handshake together get this long; then the attempt failed.
pub const HANDSHAKE_WITHIN: Duration = Duration::from_secs(4);

/// The CAs a broker's certificate must chain to, ready to connect with.
#[derive(Clone)]
pub struct BrokerTrust {
    connector: TlsConnector,
    /// The CA file, or none for the system's CAs.
    ca_file: Option<PathBuf>,
}

impl fmt::Debug for BrokerTrust {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("BrokerTrust").field("ca_file", &self.ca_file).finish_non_exhaustive()
    }
}

impl BrokerTrust {
    /// Trusts the CA certificates this system trusts (Debian's `ca-certificates`, or the
    /// file `SSL_CERT_FILE` names).
    pub fn system() -> anyhow::Result<Self> {
        let found = rustls_native_certs::load_native_certs();
        let mut roots = RootCertStore::empty();
        let (added, _unusable) = roots.add_parsable_certificates(found.certs);
        if added == 0 {
            let why = found.errors.first().map(|error| format!(" ({error})")).unwrap_or_default();
            bail!(
                "found no trusted CA certificates on this system{why}: install the \
                 ca-certificates package, or give the broker's CA with --mqtt-ca FILE"
            );
        }
        Self::with_roots(roots, None)
    }

    /// Trusts only the CA certificates in the PEM file at `path`.
    pub fn ca_file(path: &Path) -> anyhow::Result<Self> {
        let pem = std::fs::read(path)
            .with_context(|| format!("cannot read the MQTT broker's CA file {}", path.display()))?;
        let certs = CertificateDer::pem_slice_iter(&pem).collect::<Result<Vec<_>, _>>().map_err(
            |error| {
                anyhow::anyhow!(
                    "{} is not a readable PEM file ({error}); --mqtt-ca wants the CA \
                     certificate that signed the broker's, in PEM",
                    path.display()
                )
            },
        )?;
        if certs.is_empty() {
            bail!(
                "{} holds no certificate (no -----BEGIN CERTIFICATE----- block); --mqtt-ca wants \
                 the CA certificate that signed the broker's, in PEM",
                path.display()
            );
        }
        let mut roots = RootCertStore::empty();
        for cert in certs {
            roots.add(cert).map_err(|error| {
                anyhow::anyhow!(
                    "{} holds a certificate that cannot be a CA ({error}); --mqtt-ca wants the \
                     CA certificate that signed the broker's, in PEM",
                    path.display()
                )
            })?;
        }
        Self::with_roots(roots, Some(path.to_owned()))
    }

    fn with_roots(roots: RootCertStore, ca_file: Option<PathBuf>) -> anyhow::Result<Self> {
        let provider = Arc::new(rustls::crypto::aws_lc_rs::default_provider());
        let config = rustls::ClientConfig::builder_with_provider(provider)
            .with_safe_default_protocol_versions()
            .context("the TLS library offers no protocol version")?
            .with_root_certificates(roots)
            .with_no_client_auth();
        Ok(Self { connector: TlsConnector::from(Arc::new(config)), ca_file })
    }

    /// Connects to `broker` and makes the TLS handshake, its certificate checked against
    /// these CAs and the broker's host; or says in a sentence why not.
    pub async fn connect(&self, broker: &Broker) -> Result<TlsStream<TcpStream>, String> {
        let name = ServerName::try_from(broker.host.clone())
            .map_err(|_| format!("{:?} is not a name a TLS certificate can be for", broker.host))?;
        let attempt = async {
            let tcp = TcpStream::connect((broker.host.as_str(), broker.port))
                .await
                .map_err(|error| format!("cannot reach the MQTT broker at {broker}: {error}"))?;
            self.connector.connect(name, tcp).await.map_err(|error| self.refusal(broker, &error))
        };
        tokio::time::timeout(HANDSHAKE_WITHIN, attempt).await.unwrap_or_else(|_| {
            Err(format!(
                "the MQTT broker at {broker} did not complete a TLS connection within {} s: \
                 check its host, and that port {} is its TLS port",
                HANDSHAKE_WITHIN.as_secs(),
                broker.port
            ))
        })
    }

    /// Why a handshake failed, as the person setting the bridge up needs to hear it.
    fn refusal(&self, broker: &Broker, error: &io::Error) -> String {
        let tls = error.get_ref().and_then(|inner| inner.downcast_ref::<rustls::Error>());
        let trusted = match &self.ca_file {
            Some(file) => format!("the CA in {}", file.display()),
            None => "a CA this system trusts".to_owned(),
        };
        let fix = match &self.ca_file {
            Some(_) => "give the CA that signed it with --mqtt-ca",
            None => "give the CA that signed it with --mqtt-ca FILE",
        };
        let not_tls = match tls {
            Some(rustls::Error::InvalidMessage(_)) => true,
            Some(_) => false,
            // Hung up on the greeting without a TLS alert, as a plain MQTT broker does (with a
            // reset, when it leaves the rest of the greeting unread).
            None => matches!(
                error.kind(),
                io::ErrorKind::UnexpectedEof | io::ErrorKind::ConnectionReset
            ),
        };
        if not_tls {
            let plain = Broker { login: None, tls: false, ..broker.clone() };
            return format!(
                "the MQTT broker at {broker} does not speak TLS on port {}: use {plain} if that \
                 port is plain MQTT, or the broker's TLS port (usually 8883)",
                broker.port
            );
        }
        let Some(rustls::Error::InvalidCertificate(why)) = tls else {
            return format!("the TLS handshake with the MQTT broker at {broker} failed: {error}");
        };
        match why {
            CertificateError::UnknownIssuer => format!(
                "the MQTT broker at {broker} shows a certificate not signed by {trusted}: {fix} \
                 (PPS_MQTT_CA)"
            ),
            CertificateError::NotValidForName | CertificateError::NotValidForNameContext { .. } => {
                format!(
                    "the MQTT broker's certificate is not for {:?}: connect to a name its \
                     certificate lists, or give the broker a certificate for this name",
                    broker.host
                )
            }
            CertificateError::Expired | CertificateError::ExpiredContext { .. } => format!(
                "the MQTT broker at {broker} shows an expired certificate: renew it on the broker"
            ),
            CertificateError::NotValidYet | CertificateError::NotValidYetContext { .. } => format!(
                "the MQTT broker at {broker} shows a certificate that is not valid yet: check the \
                 clocks of the broker and of this server"
            ),
            other => format!(
                "the MQTT broker at {broker} shows a certificate this server cannot accept \
                 ({other:?}): give it one signed by {trusted}"
            ),
        }
    }
}
