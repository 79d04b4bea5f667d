//! One TCP connection to an LLRP reader: frames messages in and out, numbers what it sends,
//! and never waits past a deadline.

use std::io::{ErrorKind, Read, Write};
use std::net::{Shutdown, TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

use super::messages::{Message, kind, kind_name};
use super::wire::{DecodeError, MESSAGE_HEADER_LEN, MessageHeader};

/// The port IANA assigned to LLRP.
pub const LLRP_PORT: u16 = 5084;

/// Why the connection could not carry a message.
#[derive(Debug)]
pub enum Broken {
    /// The reader closed the connection, or the network failed.
    Io(String),
    /// A header that cannot be a message: the stream has lost its framing.
    Framing(DecodeError),
}

impl std::fmt::Display for Broken {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Io(reason) => f.write_str(reason),
            Self::Framing(e) => write!(f, "the reader's bytes stopped making sense ({e})"),
        }
    }
}

/// What arrived.
#[derive(Debug)]
pub enum Received {
    Message {
        id: u32,
        message: Message,
    },
    /// An RO_ACCESS_REPORT, whole but still as bytes: whoever keeps its reads decodes them one
    /// at a time ([`super::params::report::for_each_tag_report`]).
    Reports {
        bytes: Vec<u8>,
    },
    /// A whole message that did not decode; its length was sound, so the next one can be read.
    Undecodable {
        kind: String,
        error: DecodeError,
    },
}

#[derive(Debug)]
pub struct Connection {
    stream: TcpStream,
    /// Bytes read but not yet framed.
    pending: Vec<u8>,
    next_id: u32,
    pub peer: String,
    /// How long one message may take to go out: a reader that stops reading must not stall us.
    write_timeout: Duration,
    /// Why sending stopped: a message that went out in part has broken the stream's framing.
    stalled: Option<String>,
}

/// `HOST`, `HOST:PORT`, `[V6]:PORT`: the reader's address, port 5084 unless given.
pub fn with_default_port(address: &str) -> String {
    let has_port = match address.rsplit_once(':') {
        Some((host, port)) => {
            port.parse::<u16>().is_ok() && (!host.contains(':') || host.ends_with(']'))
        }
        None => false,
    };
    if has_port {
        address.to_owned()
    } else if address.contains(':') && !address.starts_with('[') {
        format!("[{address}]:{LLRP_PORT}")
    } else {
        format!("{address}:{LLRP_PORT}")
    }
}

impl Connection {
    /// Connects to `address` (`HOST[:PORT]`) within `timeout`; each message sent afterwards
    /// must go out within `write_timeout`.
    pub fn open(address: &str, timeout: Duration, write_timeout: Duration) -> Result<Self, String> {
        let peer = with_default_port(address);
        let addrs = peer
            .to_socket_addrs()
            .map_err(|e| format!("cannot resolve {peer}: {e}"))?
            .collect::<Vec<_>>();
        let mut last = format!("{peer} resolves to no address");
        for addr in addrs {
            match TcpStream::connect_timeout(&addr, timeout) {
                Ok(stream) => {
                    // Requests are small and each waits for its answer: send them at once.
                    let _ = stream.set_nodelay(true);
                    return Ok(Self {
                        stream,
                        pending: Vec::with_capacity(4096),
                        next_id: 1,
                        peer,
                        write_timeout,
                        stalled: None,
                    });
                }
                Err(e) if e.kind() == ErrorKind::TimedOut => {
                    last = format!("{peer} did not answer within {} s", timeout.as_secs_f64())
                }
                Err(e) => last = format!("cannot connect to {peer}: {e}"),
            }
        }
        Err(last)
    }

    /// Sends `message` under the next message id, which it returns.
    pub fn send(&mut self, message: &Message) -> Result<u32, Broken> {
        let id = self.next_id;
        self.next_id = self.next_id.wrapping_add(1).max(1);
        self.send_as(message, id)?;
        Ok(id)
    }

    /// Sends `message` under message id `id` (a KEEPALIVE_ACK echoes its KEEPALIVE's id).
    pub fn send_as(&mut self, message: &Message, id: u32) -> Result<(), Broken> {
        if let Some(why) = &self.stalled {
            return Err(Broken::Io(why.clone()));
        }
        let deadline = Instant::now() + self.write_timeout;
        let mut rest = &message.encode(id)[..];
        while !rest.is_empty() {
            let now = Instant::now();
            let failure = if now >= deadline {
                format!(
                    "{} stopped reading: {} did not go out within {:.1} s",
                    self.peer,
                    message.name(),
                    self.write_timeout.as_secs_f64()
                )
            } else {
                // A zero timeout means "block forever" to the OS: never pass one.
                let wait = (deadline - now).max(Duration::from_millis(1));
                self.stream.set_write_timeout(Some(wait)).map_err(|e| Broken::Io(e.to_string()))?;
                match self.stream.write(rest) {
                    Ok(0) => format!("{} closed the connection", self.peer),
                    Ok(n) => {
                        rest = &rest[n..];
                        continue;
                    }
                    Err(e)
                        if matches!(
                            e.kind(),
                            ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted
                        ) =>
                    {
                        continue;
                    }
                    Err(e) => format!("sending {} to {} failed: {e}", message.name(), self.peer),
                }
            };
            self.stalled = Some(failure.clone());
            return Err(Broken::Io(failure));
        }
        Ok(())
    }

    /// Shortens (or lengthens) how long each message may take to go out.
    pub fn set_write_timeout(&mut self, timeout: Duration) {
        self.write_timeout = timeout;
    }

    /// The next message, or `None` when `deadline` passes first.
    pub fn receive(&mut self, deadline: Instant) -> Result<Option<Received>, Broken> {
        loop {
            if let Some(frame) = self.take_frame()? {
                return Ok(Some(frame));
            }
            let now = Instant::now();
            if now >= deadline {
                return Ok(None);
            }
            // A zero timeout means "block forever" to the OS: never pass one.
            let wait = (deadline - now).max(Duration::from_millis(1));
            self.stream.set_read_timeout(Some(wait)).map_err(|e| Broken::Io(e.to_string()))?;
            let mut chunk = [0u8; 16 * 1024];
            match self.stream.read(&mut chunk) {
                Ok(0) => return Err(Broken::Io(format!("{} closed the connection", self.peer))),
                Ok(n) => self.pending.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => {
                    return Err(Broken::Io(format!("reading from {} failed: {e}", self.peer)));
                }
            }
        }
    }

    fn take_frame(&mut self) -> Result<Option<Received>, Broken> {
        if self.pending.len() < MESSAGE_HEADER_LEN {
            return Ok(None);
        }
        let header = MessageHeader::parse(&self.pending).map_err(Broken::Framing)?;
        let len = header.length as usize;
        if self.pending.len() < len {
            return Ok(None);
        }
        if header.kind == kind::RO_ACCESS_REPORT {
            // Moved out, not copied: a report may be megabytes.
            let rest = self.pending.split_off(len);
            let bytes = std::mem::replace(&mut self.pending, rest);
            return Ok(Some(Received::Reports { bytes }));
        }
        let received = match Message::decode(&self.pending[..len]) {
            Ok((id, message)) => Received::Message { id, message },
            Err(error) => Received::Undecodable { kind: kind_name(header.kind), error },
        };
        self.pending.drain(..len);
        Ok(Some(received))
    }

    pub fn shutdown(&mut self) {
        let _ = self.stream.shutdown(Shutdown::Both);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_llrp_port_is_added_when_missing() {
        assert_eq!(with_default_port("reader.local"), "reader.local:5084");
        assert_eq!(with_default_port("10.0.0.5:15084"), "10.0.0.5:15084");
        assert_eq!(with_default_port("::1"), "[::1]:5084");
        assert_eq!(with_default_port("[::1]:6000"), "[::1]:6000");
    }
}
