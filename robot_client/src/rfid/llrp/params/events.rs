//! `ReaderEventNotificationData` (LLRP 1.0.1 §16.2.7.6): what a reader tells unasked — that a
//! connection was accepted or refused, an antenna was lost, a ROSpec started or ended, or the
//! reader itself failed.

use super::super::wire::{DecodeError, Decoded, Param, tlv, utf8v};

pub const READER_EVENT_NOTIFICATION_DATA: u16 = 246;
const UTC_TIMESTAMP: u16 = 128;
const UPTIME: u16 = 129;
const ROSPEC_EVENT: u16 = 249;
const READER_EXCEPTION_EVENT: u16 = 252;
const ANTENNA_EVENT: u16 = 255;
const CONNECTION_ATTEMPT_EVENT: u16 = 256;
const CONNECTION_CLOSE_EVENT: u16 = 257;

/// When the reader says the event happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventTimestamp {
    /// Microseconds since 1970-01-01 UTC.
    Utc(u64),
    /// Microseconds since the reader booted.
    Uptime(u64),
}

/// One notification; a reader may put several events in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReaderEventNotificationData {
    pub timestamp: EventTimestamp,
    pub connection_attempt: Option<ConnectionAttemptStatus>,
    pub antenna: Option<AntennaEvent>,
    pub rospec: Option<RoSpecEvent>,
    /// The reader's own description of a failure.
    pub reader_exception: Option<String>,
    /// The reader is about to close the connection.
    pub connection_close: bool,
}

/// `ConnectionAttemptEvent`'s status.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConnectionAttemptStatus {
    Success,
    ReaderInitiatedConnectionExists,
    ClientInitiatedConnectionExists,
    OtherReason,
    AnotherConnectionAttempted,
    Unknown(u16),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AntennaEvent {
    pub connected: bool,
    pub antenna_id: u16,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoSpecEventKind {
    Start,
    End,
    Preempted,
    Unknown(u8),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoSpecEvent {
    pub kind: RoSpecEventKind,
    pub rospec_id: u32,
    pub preempting_rospec_id: u32,
}

impl ConnectionAttemptStatus {
    fn from_code(code: u16) -> Self {
        match code {
            0 => Self::Success,
            1 => Self::ReaderInitiatedConnectionExists,
            2 => Self::ClientInitiatedConnectionExists,
            3 => Self::OtherReason,
            4 => Self::AnotherConnectionAttempted,
            other => Self::Unknown(other),
        }
    }

    fn code(self) -> u16 {
        match self {
            Self::Success => 0,
            Self::ReaderInitiatedConnectionExists => 1,
            Self::ClientInitiatedConnectionExists => 2,
            Self::OtherReason => 3,
            Self::AnotherConnectionAttempted => 4,
            Self::Unknown(code) => code,
        }
    }

    /// Why the reader refused, in words; `None` when it accepted.
    pub fn refusal(self) -> Option<String> {
        Some(match self {
            Self::Success => return None,
            Self::ReaderInitiatedConnectionExists => {
                "it already has a connection it opened itself".to_owned()
            }
            Self::ClientInitiatedConnectionExists => {
                "another client is connected to it (a reader takes one at a time)".to_owned()
            }
            Self::OtherReason => "it refused for a reason other than another connection".to_owned(),
            Self::AnotherConnectionAttempted => "another client tried to connect".to_owned(),
            Self::Unknown(code) => format!("it answered with connection status {code}"),
        })
    }
}

impl RoSpecEventKind {
    fn from_code(code: u8) -> Self {
        match code {
            0 => Self::Start,
            1 => Self::End,
            2 => Self::Preempted,
            other => Self::Unknown(other),
        }
    }

    fn code(self) -> u8 {
        match self {
            Self::Start => 0,
            Self::End => 1,
            Self::Preempted => 2,
            Self::Unknown(code) => code,
        }
    }
}

impl ReaderEventNotificationData {
    /// A notification carrying only a timestamp; set the events it reports.
    pub fn at(timestamp: EventTimestamp) -> Self {
        Self {
            timestamp,
            connection_attempt: None,
            antenna: None,
            rospec: None,
            reader_exception: None,
            connection_close: false,
        }
    }

    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, READER_EVENT_NOTIFICATION_DATA, |out| {
            let (kind, micros) = match self.timestamp {
                EventTimestamp::Utc(us) => (UTC_TIMESTAMP, us),
                EventTimestamp::Uptime(us) => (UPTIME, us),
            };
            tlv(out, kind, |out| out.extend_from_slice(&micros.to_be_bytes()));
            if let Some(e) = self.rospec {
                tlv(out, ROSPEC_EVENT, |out| {
                    out.push(e.kind.code());
                    out.extend_from_slice(&e.rospec_id.to_be_bytes());
                    out.extend_from_slice(&e.preempting_rospec_id.to_be_bytes());
                });
            }
            if let Some(message) = &self.reader_exception {
                tlv(out, READER_EXCEPTION_EVENT, |out| utf8v(out, message));
            }
            if let Some(e) = self.antenna {
                tlv(out, ANTENNA_EVENT, |out| {
                    out.push(u8::from(e.connected));
                    out.extend_from_slice(&e.antenna_id.to_be_bytes());
                });
            }
            if let Some(status) = self.connection_attempt {
                tlv(out, CONNECTION_ATTEMPT_EVENT, |out| {
                    out.extend_from_slice(&status.code().to_be_bytes())
                });
            }
            if self.connection_close {
                tlv(out, CONNECTION_CLOSE_EVENT, |_| {});
            }
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let mut timestamp = None;
        let mut data = Self::at(EventTimestamp::Uptime(0));
        while let Some(p) = r.param()? {
            let mut f = p.fields();
            match p.kind {
                UTC_TIMESTAMP => timestamp = Some(EventTimestamp::Utc(f.u64("UTCTimestamp")?)),
                UPTIME => timestamp = Some(EventTimestamp::Uptime(f.u64("Uptime")?)),
                ROSPEC_EVENT => {
                    data.rospec = Some(RoSpecEvent {
                        kind: RoSpecEventKind::from_code(f.u8("ROSpecEvent's type")?),
                        rospec_id: f.u32("ROSpecEvent's ROSpecID")?,
                        preempting_rospec_id: f.u32("ROSpecEvent's preempting ROSpecID")?,
                    })
                }
                READER_EXCEPTION_EVENT => {
                    data.reader_exception = Some(f.utf8v("ReaderExceptionEvent's message")?)
                }
                ANTENNA_EVENT => {
                    data.antenna = Some(AntennaEvent {
                        connected: f.u8("AntennaEvent's type")? == 1,
                        antenna_id: f.u16("AntennaEvent's AntennaID")?,
                    })
                }
                CONNECTION_ATTEMPT_EVENT => {
                    data.connection_attempt = Some(ConnectionAttemptStatus::from_code(
                        f.u16("ConnectionAttemptEvent's status")?,
                    ))
                }
                CONNECTION_CLOSE_EVENT => data.connection_close = true,
                // Hopping, GPI, buffer, RF survey and AISpec events, and vendors' own: not ours.
                _ => {}
            }
        }
        data.timestamp = timestamp.ok_or_else(|| {
            DecodeError("ReaderEventNotificationData has no timestamp".to_owned())
        })?;
        Ok(data)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rfid::llrp::wire::FieldReader;

    fn round_trip(data: &ReaderEventNotificationData) -> ReaderEventNotificationData {
        let mut bytes = Vec::new();
        data.encode(&mut bytes);
        let mut r = FieldReader::new(&bytes);
        ReaderEventNotificationData::decode(r.param().unwrap().unwrap()).unwrap()
    }

    #[test]
    fn every_event_we_act_on_round_trips() {
        let mut data = ReaderEventNotificationData::at(EventTimestamp::Utc(1_764_000_000_000_000));
        data.connection_attempt = Some(ConnectionAttemptStatus::ClientInitiatedConnectionExists);
        data.antenna = Some(AntennaEvent { connected: false, antenna_id: 2 });
        data.rospec = Some(RoSpecEvent {
            kind: RoSpecEventKind::End,
            rospec_id: 14,
            preempting_rospec_id: 0,
        });
        data.reader_exception = Some("PA overheated".into());
        data.connection_close = true;
        assert_eq!(round_trip(&data), data);
        let plain = ReaderEventNotificationData::at(EventTimestamp::Uptime(5));
        assert_eq!(round_trip(&plain), plain);
    }
}
