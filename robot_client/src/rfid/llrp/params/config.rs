//! The reader settings SET_READER_CONFIG carries (LLRP 1.0.1 §12): which events the reader
//! notifies, and how often it sends a keepalive.

use super::super::wire::{Decoded, FieldReader, Param, tlv};

pub const READER_EVENT_NOTIFICATION_SPEC: u16 = 244;
const EVENT_NOTIFICATION_STATE: u16 = 245;
pub const KEEPALIVE_SPEC: u16 = 220;

/// `EventNotificationState`'s event types that the client acts on.
pub mod event_type {
    pub const ROSPEC_EVENT: u16 = 2;
    pub const READER_EXCEPTION_EVENT: u16 = 4;
    pub const ANTENNA_EVENT: u16 = 8;
}

/// Which events to notify: (event type, on or off).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReaderEventNotificationSpec {
    pub states: Vec<(u16, bool)>,
}

/// A keepalive every `period_ms` milliseconds, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KeepaliveSpec {
    pub period_ms: Option<u32>,
}

impl ReaderEventNotificationSpec {
    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, READER_EVENT_NOTIFICATION_SPEC, |out| {
            for &(kind, on) in &self.states {
                tlv(out, EVENT_NOTIFICATION_STATE, |out| {
                    out.extend_from_slice(&kind.to_be_bytes());
                    out.push(u8::from(on) << 7);
                });
            }
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r: FieldReader<'_> = param.fields();
        let mut states = Vec::new();
        while let Some(p) = r.param()? {
            if p.kind == EVENT_NOTIFICATION_STATE {
                let mut f = p.fields();
                let kind = f.u16("EventNotificationState's event type")?;
                states.push((kind, f.u8("EventNotificationState's state")? & 0x80 != 0));
            }
        }
        Ok(Self { states })
    }
}

impl KeepaliveSpec {
    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, KEEPALIVE_SPEC, |out| {
            out.push(u8::from(self.period_ms.is_some()));
            out.extend_from_slice(&self.period_ms.unwrap_or(0).to_be_bytes());
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut f = param.fields();
        let kind = f.u8("KeepaliveSpec's trigger type")?;
        let period = f.u32("KeepaliveSpec's period")?;
        Ok(Self { period_ms: (kind == 1).then_some(period) })
    }
}
