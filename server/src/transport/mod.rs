//! How the registry accepts connections: plain TCP or TLS, HTTP/1.1, at most so many
//! connections at once (and a share of them per client address), and deadlines for every
//! request head and body.
//!
//! The deadlines are what keep a client that trickles its headers or body (or never finishes
//! a TLS handshake) from holding a connection forever; the cap is what keeps many such
//! clients from exhausting file descriptors, and the per-address share what keeps one host
//! from taking every connection. This module serves whatever router it is given and knows
//! nothing of the API. It must never drop a request in flight at shutdown: it stops accepting,
//! lets open requests finish and closes idle connections.

mod address_share;
pub mod answer_turns;
pub mod body_deadline;
pub mod tls;
mod write_deadline;

use std::future::Future;
use std::io;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use http_body::Body as _;
use hyper::server::conn::http1;
use hyper_util::rt::{TokioIo, TokioTimer};
use tokio::io::{AsyncRead, AsyncWrite};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{OwnedSemaphorePermit, Semaphore, watch};
use tower::ServiceExt;

use address_share::{AddressShares, AddressSlot};
pub use answer_turns::AnswerTurns;
use body_deadline::DeadlineBody;
pub use tls::TlsIdentity;
use write_deadline::WriteDeadline;

/// Generous for a LAN; a robot on flaky Wi-Fi still gets its request head through.
pub const DEFAULT_HEADER_READ_TIMEOUT: Duration = Duration::from_secs(30);
/// Room for every change-feed client (`feed::MAX_CLIENTS`) plus as many again for requests.
pub const DEFAULT_MAX_CONNECTIONS: u32 = 512;
/// A small share: a browser opens six connections and its change feed, a robot a few and its
/// feed. Once half of the connections are in use no address gets more, so two hosts can no
/// longer hold them all.
pub const DEFAULT_MAX_CONNECTIONS_PER_ADDRESS: u32 = 16;
/// A 1 MiB trial crosses even a poor Wi-Fi link in a few seconds.
pub const DEFAULT_BODY_READ_TIMEOUT: Duration = Duration::from_secs(30);
/// A client that stops reading is cut off after this; an honest one on poor Wi-Fi takes a
/// response of a few megabytes well within it, as the kernel buffers much of it.
pub const DEFAULT_WRITE_TIMEOUT: Duration = Duration::from_secs(30);
/// The longest any connection timeout may be: an hour is already no protection, and a timer
/// much further out overflows the clock.
pub const MAX_TIMEOUT: Duration = Duration::from_secs(3600);

/// Marks a request that arrived over TLS (so cookies may carry `Secure`).
#[derive(Debug, Clone, Copy)]
pub struct SecureTransport;

/// How connections are accepted and held.
#[derive(Debug, Clone)]
pub struct Transport {
    /// How long a client has to deliver a request head: from connecting (including the TLS
    /// handshake) or from the end of its previous response. An idle keep-alive connection is
    /// closed after this too.
    pub header_read_timeout: Duration,
    /// Connections served at once; further clients wait in the listen backlog until one
    /// closes.
    pub max_connections: usize,
    /// Connections one client address may hold at once when half of `max_connections` are in
    /// use; beyond, its new connections are closed at once.
    pub max_connections_per_address: usize,
    /// How long a client has to deliver a request body, from the end of its head; then it is
    /// answered 408 and the connection closes.
    pub body_read_timeout: Duration,
    /// How long a client may leave a response waiting, from the first write its connection
    /// refuses until all of it is taken; then the connection closes.
    pub write_timeout: Duration,
    /// Serve HTTPS with this certificate; plain HTTP when `None`.
    pub tls: Option<TlsIdentity>,
}

impl Default for Transport {
    fn default() -> Self {
        Self {
            header_read_timeout: DEFAULT_HEADER_READ_TIMEOUT,
            max_connections: DEFAULT_MAX_CONNECTIONS as usize,
            max_connections_per_address: DEFAULT_MAX_CONNECTIONS_PER_ADDRESS as usize,
            body_read_timeout: DEFAULT_BODY_READ_TIMEOUT,
            write_timeout: DEFAULT_WRITE_TIMEOUT,
            tls: None,
        }
    }
}

impl Transport {
    /// `https` or `http`, for URLs shown to people.
    pub fn scheme(&self) -> &'static str {
        if self.tls.is_some() { "https" } else { "http" }
    }
}

/// Serves `app` on `listener` until `shutdown` completes, then waits for open requests.
pub async fn serve(
    listener: TcpListener,
    app: Router,
    transport: &Transport,
    shutdown: impl Future<Output = ()>,
) -> io::Result<()> {
    let mut http = http1::Builder::new();
    http.timer(TokioTimer::new())
        .header_read_timeout(transport.header_read_timeout.min(MAX_TIMEOUT));
    let slots = Arc::new(Semaphore::new(transport.max_connections.max(1)));
    let shares =
        AddressShares::new(transport.max_connections_per_address, transport.max_connections);
    // Every connection holds a receiver; the sender learns when the last one is gone.
    let (closing, watch_closing) = watch::channel(false);
    tokio::pin!(shutdown);
    loop {
        let accepted = tokio::select! {
            biased;
            () = &mut shutdown => break,
            accepted = accept(&listener, &slots) => accepted,
        };
        let Some((stream, peer, slot)) = accepted else { continue };
        let Some(share) = shares.claim(peer.ip()) else {
            tracing::debug!(%peer, "closed a connection beyond its address's share");
            continue;
        };
        let connection = Connection {
            peer,
            body_read_timeout: transport.body_read_timeout.min(MAX_TIMEOUT),
            write_timeout: transport.write_timeout.min(MAX_TIMEOUT),
            http: http.clone(),
            app: app.clone(),
            tls: transport.tls.clone(),
            handshake_timeout: transport.header_read_timeout.min(MAX_TIMEOUT),
            closing: watch_closing.clone(),
            _slots: (slot, share),
        };
        tokio::spawn(connection.serve(stream));
    }
    drop(listener);
    drop(watch_closing);
    closing.send_replace(true);
    closing.closed().await;
    Ok(())
}

/// The next connection, once there is room for it; `None` after a failed accept.
async fn accept(
    listener: &TcpListener,
    slots: &Arc<Semaphore>,
) -> Option<(TcpStream, SocketAddr, OwnedSemaphorePermit)> {
    // Take a slot before accepting: beyond the cap, clients wait in the kernel's backlog.
    let slot = slots.clone().acquire_owned().await.expect("the semaphore is never closed");
    match listener.accept().await {
        Ok((stream, peer)) => Some((stream, peer, slot)),
        Err(error) => {
            pause_after(&error).await;
            None
        }
    }
}

/// A client that gave up during the handshake is nothing to wait on; running out of file
/// descriptors is, or the loop would spin.
async fn pause_after(error: &io::Error) {
    use io::ErrorKind::{ConnectionAborted, ConnectionRefused, ConnectionReset};
    if matches!(error.kind(), ConnectionAborted | ConnectionRefused | ConnectionReset) {
        return;
    }
    tracing::error!(%error, "cannot accept connections; retrying in a second");
    #[allow(
        clippy::disallowed_methods,
        reason = "a failing accept is retried after a pause, not in a busy loop"
    )]
    tokio::time::sleep(Duration::from_secs(1)).await;
}

/// One accepted connection, holding its slot until it closes.
struct Connection {
    /// The client's address, for the login slow-down.
    peer: SocketAddr,
    body_read_timeout: Duration,
    write_timeout: Duration,
    http: http1::Builder,
    app: Router,
    tls: Option<TlsIdentity>,
    handshake_timeout: Duration,
    closing: watch::Receiver<bool>,
    _slots: (OwnedSemaphorePermit, AddressSlot),
}

impl Connection {
    async fn serve(mut self, stream: TcpStream) {
        // Responses are written whole; waiting to coalesce them only adds latency.
        let _ = stream.set_nodelay(true);
        let Some(tls) = self.tls.take() else {
            return self.serve_http(stream, false).await;
        };
        let handshake = tokio::time::timeout(self.handshake_timeout, tls.accept(stream));
        let stream = tokio::select! {
            finished = handshake => match finished {
                Ok(Ok(stream)) => stream,
                Ok(Err(error)) => {
                    tracing::debug!(%error, "TLS handshake failed");
                    return;
                }
                Err(_) => {
                    tracing::debug!("TLS handshake timed out");
                    return;
                }
            },
            () = closing(&mut self.closing) => return,
        };
        self.serve_http(stream, true).await;
    }

    async fn serve_http(
        mut self,
        io: impl AsyncRead + AsyncWrite + Unpin + Send + 'static,
        secure: bool,
    ) {
        let (app, peer, body_limit) = (self.app, self.peer, self.body_read_timeout);
        let service = hyper::service::service_fn(move |request: hyper::Request<_>| {
            // Bodiless requests (the robots' hot path) need no timer.
            let mut request = request.map(|body: hyper::body::Incoming| {
                if body.is_end_stream() {
                    axum::body::Body::new(body)
                } else {
                    axum::body::Body::new(DeadlineBody::new(body, body_limit))
                }
            });
            request.extensions_mut().insert(axum::extract::ConnectInfo(peer));
            if secure {
                request.extensions_mut().insert(SecureTransport);
            }
            app.clone().oneshot(request)
        });
        let io = WriteDeadline::new(io, self.write_timeout);
        let connection = self.http.serve_connection(TokioIo::new(io), service);
        tokio::pin!(connection);
        let ended = tokio::select! {
            ended = connection.as_mut() => ended,
            () = closing(&mut self.closing) => {
                // Finishes the request in flight, if any, then closes.
                connection.as_mut().graceful_shutdown();
                connection.await
            }
        };
        if let Err(error) = ended {
            tracing::debug!(%error, "connection ended early");
        }
    }
}

/// Completes when the server starts shutting down.
async fn closing(closing: &mut watch::Receiver<bool>) {
    let _ = closing.wait_for(|closing| *closing).await;
}
