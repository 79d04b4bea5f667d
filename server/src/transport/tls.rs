//! HTTPS on the LAN: the server's certificate and private key from PEM files, served with
//! rustls and its aws-lc-rs provider.
//!
//! Everything that can be wrong with the files is found here, at start, with a message that
//! names the file and what to do; the server must never start with a key that does not belong
//! to its certificate.

use std::fmt;
use std::path::Path;
use std::sync::Arc;

use anyhow::{Context, bail};
use rustls::pki_types::pem::PemObject;
use rustls::pki_types::{CertificateDer, PrivateKeyDer};
use tokio::net::TcpStream;
use tokio_rustls::TlsAcceptor;
use tokio_rustls::server::TlsStream;

/// The certificate and key the server proves itself with.
#[derive(Clone)]
pub struct TlsIdentity {
    acceptor: TlsAcceptor,
}

impl fmt::Debug for TlsIdentity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TlsIdentity").finish_non_exhaustive()
    }
}

impl TlsIdentity {
    /// Loads a PEM certificate chain (the server's first, then any intermediates) and the PEM
    /// private key that belongs to it (PKCS#8, PKCS#1 or SEC1).
    pub fn load(cert_path: &Path, key_path: &Path) -> anyhow::Result<Self> {
        let certs = read_certificates(cert_path)?;
        let key = read_private_key(key_path)?;
        let provider = Arc::new(rustls::crypto::aws_lc_rs::default_provider());
        let mut config = rustls::ServerConfig::builder_with_provider(provider)
            .with_safe_default_protocol_versions()
            .context("the TLS library offers no protocol version")?
            .with_no_client_auth()
            .with_single_cert(certs, key)
            .map_err(|error| match error {
                rustls::Error::InconsistentKeys(_) => anyhow::anyhow!(
                    "the private key {} does not belong to the certificate {}: give the key \
                     that was made together with that certificate",
                    key_path.display(),
                    cert_path.display()
                ),
                other => anyhow::anyhow!(
                    "cannot serve TLS with the certificate {} and the key {}: {other}",
                    cert_path.display(),
                    key_path.display()
                ),
            })?;
        config.alpn_protocols = vec![b"http/1.1".to_vec()];
        Ok(Self { acceptor: TlsAcceptor::from(Arc::new(config)) })
    }

    /// Runs the server side of a TLS handshake.
    pub async fn accept(&self, stream: TcpStream) -> std::io::Result<TlsStream<TcpStream>> {
        self.acceptor.accept(stream).await
    }
}

fn read_pem(path: &Path, what: &str) -> anyhow::Result<Vec<u8>> {
    std::fs::read(path).with_context(|| format!("cannot read the TLS {what} {}", path.display()))
}

fn read_certificates(path: &Path) -> anyhow::Result<Vec<CertificateDer<'static>>> {
    let pem = read_pem(path, "certificate")?;
    let certs = CertificateDer::pem_slice_iter(&pem)
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("{} is not a readable PEM file", path.display()))?;
    if certs.is_empty() {
        bail!(
            "{} holds no certificate (no -----BEGIN CERTIFICATE----- block); --tls-cert wants \
             the server's certificate in PEM, followed by any intermediates",
            path.display()
        );
    }
    Ok(certs)
}

fn read_private_key(path: &Path) -> anyhow::Result<PrivateKeyDer<'static>> {
    let pem = read_pem(path, "private key")?;
    PrivateKeyDer::from_pem_slice(&pem).map_err(|error| match error {
        rustls::pki_types::pem::Error::NoItemsFound => anyhow::anyhow!(
            "{} holds no private key (no -----BEGIN PRIVATE KEY----- block or its RSA or EC \
             form); --tls-key wants the certificate's private key in PEM",
            path.display()
        ),
        other => anyhow::anyhow!("{} is not a readable PEM private key: {other}", path.display()),
    })
}
