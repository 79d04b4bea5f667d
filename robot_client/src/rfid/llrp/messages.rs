//! LLRP messages (LLRP 1.0.1 §17.1): one variant per message the client sends or handles, each
//! encoded to and decoded from its exact bytes.
//!
//! A message of a type not listed here decodes as [`Message::Other`] with its type, so a reader
//! that sends something new (a vendor's CUSTOM_MESSAGE, a GET_READER_CONFIG_RESPONSE) is
//! logged, not fatal.
//!
//! Long because it is one table, a variant per message with its encoding beside it; a quarter
//! of the file is the tests that hold each to its bytes.

use super::params::capabilities::{
    GENERAL_DEVICE_CAPABILITIES, GeneralDeviceCapabilities, REGULATORY_CAPABILITIES,
    RegulatoryCapabilities,
};
use super::params::config::{
    KEEPALIVE_SPEC, KeepaliveSpec, READER_EVENT_NOTIFICATION_SPEC, ReaderEventNotificationSpec,
};
use super::params::events::{READER_EVENT_NOTIFICATION_DATA, ReaderEventNotificationData};
use super::params::report::{TagReportData, decode_tag_reports};
use super::params::rospec::{ROSPEC, RoSpec, decode_rospecs};
use super::params::status::LlrpStatus;
use super::wire::{DecodeError, Decoded, FieldReader, MESSAGE_HEADER_LEN, MessageHeader, message};

/// Message types (LLRP 1.0.1 Table 17.1).
pub mod kind {
    pub const GET_READER_CAPABILITIES: u16 = 1;
    pub const SET_READER_CONFIG: u16 = 3;
    pub const CLOSE_CONNECTION_RESPONSE: u16 = 4;
    pub const GET_READER_CAPABILITIES_RESPONSE: u16 = 11;
    pub const SET_READER_CONFIG_RESPONSE: u16 = 13;
    pub const CLOSE_CONNECTION: u16 = 14;
    pub const ADD_ROSPEC: u16 = 20;
    pub const DELETE_ROSPEC: u16 = 21;
    pub const START_ROSPEC: u16 = 22;
    pub const STOP_ROSPEC: u16 = 23;
    pub const ENABLE_ROSPEC: u16 = 24;
    pub const DISABLE_ROSPEC: u16 = 25;
    pub const GET_ROSPECS: u16 = 26;
    pub const ADD_ROSPEC_RESPONSE: u16 = 30;
    pub const DELETE_ROSPEC_RESPONSE: u16 = 31;
    pub const START_ROSPEC_RESPONSE: u16 = 32;
    pub const STOP_ROSPEC_RESPONSE: u16 = 33;
    pub const ENABLE_ROSPEC_RESPONSE: u16 = 34;
    pub const DISABLE_ROSPEC_RESPONSE: u16 = 35;
    pub const GET_ROSPECS_RESPONSE: u16 = 36;
    pub const RO_ACCESS_REPORT: u16 = 61;
    pub const KEEPALIVE: u16 = 62;
    pub const READER_EVENT_NOTIFICATION: u16 = 63;
    pub const KEEPALIVE_ACK: u16 = 72;
    pub const ERROR_MESSAGE: u16 = 100;
}

/// `GET_READER_CAPABILITIES`' RequestedData: 0 asks for everything.
pub const ALL_CAPABILITIES: u8 = 0;

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Message {
    GetReaderCapabilities {
        requested_data: u8,
    },
    GetReaderCapabilitiesResponse {
        status: LlrpStatus,
        general: Option<GeneralDeviceCapabilities>,
        regulatory: Option<RegulatoryCapabilities>,
    },
    SetReaderConfig(SetReaderConfig),
    SetReaderConfigResponse {
        status: LlrpStatus,
    },
    GetRoSpecs,
    GetRoSpecsResponse {
        status: LlrpStatus,
        rospecs: Vec<RoSpec>,
    },
    AddRoSpec {
        rospec: RoSpec,
    },
    AddRoSpecResponse {
        status: LlrpStatus,
    },
    DeleteRoSpec {
        rospec_id: u32,
    },
    DeleteRoSpecResponse {
        status: LlrpStatus,
    },
    EnableRoSpec {
        rospec_id: u32,
    },
    EnableRoSpecResponse {
        status: LlrpStatus,
    },
    /// Stops and disables a ROSpec; ROSpecID 0 means every ROSpec of the reader.
    DisableRoSpec {
        rospec_id: u32,
    },
    DisableRoSpecResponse {
        status: LlrpStatus,
    },
    StartRoSpec {
        rospec_id: u32,
    },
    StartRoSpecResponse {
        status: LlrpStatus,
    },
    StopRoSpec {
        rospec_id: u32,
    },
    StopRoSpecResponse {
        status: LlrpStatus,
    },
    RoAccessReport {
        tags: Vec<TagReportData>,
    },
    Keepalive,
    KeepaliveAck,
    ReaderEventNotification {
        data: ReaderEventNotificationData,
    },
    ErrorMessage {
        status: LlrpStatus,
    },
    CloseConnection,
    CloseConnectionResponse {
        status: LlrpStatus,
    },
    /// A message type the client does not decode.
    Other {
        kind: u16,
    },
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SetReaderConfig {
    pub reset_to_factory_default: bool,
    pub event_notifications: Option<ReaderEventNotificationSpec>,
    pub keepalive: Option<KeepaliveSpec>,
}

impl Message {
    /// The message's type number.
    pub fn kind(&self) -> u16 {
        use kind::*;
        match self {
            Self::GetReaderCapabilities { .. } => GET_READER_CAPABILITIES,
            Self::GetReaderCapabilitiesResponse { .. } => GET_READER_CAPABILITIES_RESPONSE,
            Self::SetReaderConfig(_) => SET_READER_CONFIG,
            Self::SetReaderConfigResponse { .. } => SET_READER_CONFIG_RESPONSE,
            Self::GetRoSpecs => GET_ROSPECS,
            Self::GetRoSpecsResponse { .. } => GET_ROSPECS_RESPONSE,
            Self::AddRoSpec { .. } => ADD_ROSPEC,
            Self::AddRoSpecResponse { .. } => ADD_ROSPEC_RESPONSE,
            Self::DeleteRoSpec { .. } => DELETE_ROSPEC,
            Self::DeleteRoSpecResponse { .. } => DELETE_ROSPEC_RESPONSE,
            Self::EnableRoSpec { .. } => ENABLE_ROSPEC,
            Self::EnableRoSpecResponse { .. } => ENABLE_ROSPEC_RESPONSE,
            Self::DisableRoSpec { .. } => DISABLE_ROSPEC,
            Self::DisableRoSpecResponse { .. } => DISABLE_ROSPEC_RESPONSE,
            Self::StartRoSpec { .. } => START_ROSPEC,
            Self::StartRoSpecResponse { .. } => START_ROSPEC_RESPONSE,
            Self::StopRoSpec { .. } => STOP_ROSPEC,
            Self::StopRoSpecResponse { .. } => STOP_ROSPEC_RESPONSE,
            Self::RoAccessReport { .. } => RO_ACCESS_REPORT,
            Self::Keepalive => KEEPALIVE,
            Self::KeepaliveAck => KEEPALIVE_ACK,
            Self::ReaderEventNotification { .. } => READER_EVENT_NOTIFICATION,
            Self::ErrorMessage { .. } => ERROR_MESSAGE,
            Self::CloseConnection => CLOSE_CONNECTION,
            Self::CloseConnectionResponse { .. } => CLOSE_CONNECTION_RESPONSE,
            Self::Other { kind } => *kind,
        }
    }

    /// The spec's name of the message, for log lines and errors.
    pub fn name(&self) -> String {
        kind_name(self.kind())
    }

    /// The status a response carries, if it is a response.
    pub fn status(&self) -> Option<&LlrpStatus> {
        match self {
            Self::GetReaderCapabilitiesResponse { status, .. }
            | Self::SetReaderConfigResponse { status }
            | Self::GetRoSpecsResponse { status, .. }
            | Self::AddRoSpecResponse { status }
            | Self::DeleteRoSpecResponse { status }
            | Self::EnableRoSpecResponse { status }
            | Self::DisableRoSpecResponse { status }
            | Self::StartRoSpecResponse { status }
            | Self::StopRoSpecResponse { status }
            | Self::ErrorMessage { status }
            | Self::CloseConnectionResponse { status } => Some(status),
            _ => None,
        }
    }

    /// The whole message, header included, under message id `id`.
    pub fn encode(&self, id: u32) -> Vec<u8> {
        message(self.kind(), id, |out| match self {
            Self::GetReaderCapabilities { requested_data } => out.push(*requested_data),
            Self::GetReaderCapabilitiesResponse { status, general, regulatory } => {
                status.encode(out);
                if let Some(general) = general {
                    general.encode(out);
                }
                if let Some(regulatory) = regulatory {
                    regulatory.encode(out);
                }
            }
            Self::SetReaderConfig(config) => {
                out.push(u8::from(config.reset_to_factory_default) << 7);
                if let Some(events) = &config.event_notifications {
                    events.encode(out);
                }
                if let Some(keepalive) = &config.keepalive {
                    keepalive.encode(out);
                }
            }
            Self::GetRoSpecsResponse { status, rospecs } => {
                status.encode(out);
                for spec in rospecs {
                    spec.encode(out);
                }
            }
            Self::AddRoSpec { rospec } => rospec.encode(out),
            Self::DeleteRoSpec { rospec_id }
            | Self::EnableRoSpec { rospec_id }
            | Self::DisableRoSpec { rospec_id }
            | Self::StartRoSpec { rospec_id }
            | Self::StopRoSpec { rospec_id } => out.extend_from_slice(&rospec_id.to_be_bytes()),
            Self::RoAccessReport { tags } => {
                for tag in tags {
                    tag.encode(out);
                }
            }
            Self::ReaderEventNotification { data } => data.encode(out),
            Self::SetReaderConfigResponse { status }
            | Self::AddRoSpecResponse { status }
            | Self::DeleteRoSpecResponse { status }
            | Self::EnableRoSpecResponse { status }
            | Self::DisableRoSpecResponse { status }
            | Self::StartRoSpecResponse { status }
            | Self::StopRoSpecResponse { status }
            | Self::ErrorMessage { status }
            | Self::CloseConnectionResponse { status } => status.encode(out),
            Self::GetRoSpecs
            | Self::Keepalive
            | Self::KeepaliveAck
            | Self::CloseConnection
            | Self::Other { .. } => {}
        })
    }

    /// One whole message (header and body, exactly as long as its length field says), with
    /// its id.
    pub fn decode(bytes: &[u8]) -> Decoded<(u32, Self)> {
        if bytes.len() < MESSAGE_HEADER_LEN {
            return Err(DecodeError(format!(
                "a message of {} bytes is shorter than the 10-byte header",
                bytes.len()
            )));
        }
        let header = MessageHeader::parse(bytes)?;
        if header.length as usize != bytes.len() {
            return Err(DecodeError(format!(
                "{} says it is {} bytes long but {} arrived",
                kind_name(header.kind),
                header.length,
                bytes.len()
            )));
        }
        let mut r = FieldReader::new(&bytes[MESSAGE_HEADER_LEN..]);
        let message = Self::decode_body(header.kind, &mut r)
            .map_err(|e| DecodeError(format!("{}: {e}", kind_name(header.kind))))?;
        Ok((header.id, message))
    }

    fn decode_body(kind: u16, r: &mut FieldReader<'_>) -> Decoded<Self> {
        use kind::*;
        let name = kind_name(kind);
        let rospec_id = |r: &mut FieldReader<'_>| r.u32("its ROSpecID");
        Ok(match kind {
            GET_READER_CAPABILITIES => {
                Self::GetReaderCapabilities { requested_data: r.u8("its requested data")? }
            }
            GET_READER_CAPABILITIES_RESPONSE => {
                let status = LlrpStatus::first_in(r, &name)?;
                let (mut general, mut regulatory) = (None, None);
                while let Some(p) = r.param()? {
                    match p.kind {
                        GENERAL_DEVICE_CAPABILITIES => {
                            general = Some(GeneralDeviceCapabilities::decode(p)?)
                        }
                        REGULATORY_CAPABILITIES => {
                            regulatory = Some(RegulatoryCapabilities::decode(p)?)
                        }
                        _ => {}
                    }
                }
                Self::GetReaderCapabilitiesResponse { status, general, regulatory }
            }
            SET_READER_CONFIG => {
                let mut config = SetReaderConfig {
                    reset_to_factory_default: r.u8("its reset flag")? & 0x80 != 0,
                    event_notifications: None,
                    keepalive: None,
                };
                while let Some(p) = r.param()? {
                    match p.kind {
                        READER_EVENT_NOTIFICATION_SPEC => {
                            config.event_notifications =
                                Some(ReaderEventNotificationSpec::decode(p)?)
                        }
                        KEEPALIVE_SPEC => config.keepalive = Some(KeepaliveSpec::decode(p)?),
                        _ => {}
                    }
                }
                Self::SetReaderConfig(config)
            }
            GET_ROSPECS => Self::GetRoSpecs,
            GET_ROSPECS_RESPONSE => {
                let status = LlrpStatus::first_in(r, &name)?;
                Self::GetRoSpecsResponse { status, rospecs: decode_rospecs(r)? }
            }
            ADD_ROSPEC => match r.param()? {
                Some(p) if p.kind == ROSPEC => Self::AddRoSpec { rospec: RoSpec::decode(p)? },
                _ => return Err(DecodeError("it carries no ROSpec".to_owned())),
            },
            DELETE_ROSPEC => Self::DeleteRoSpec { rospec_id: rospec_id(r)? },
            ENABLE_ROSPEC => Self::EnableRoSpec { rospec_id: rospec_id(r)? },
            DISABLE_ROSPEC => Self::DisableRoSpec { rospec_id: rospec_id(r)? },
            START_ROSPEC => Self::StartRoSpec { rospec_id: rospec_id(r)? },
            STOP_ROSPEC => Self::StopRoSpec { rospec_id: rospec_id(r)? },
            RO_ACCESS_REPORT => {
                let mut tags = Vec::new();
                decode_tag_reports(r, &mut tags)?;
                Self::RoAccessReport { tags }
            }
            KEEPALIVE => Self::Keepalive,
            KEEPALIVE_ACK => Self::KeepaliveAck,
            READER_EVENT_NOTIFICATION => match r.param()? {
                Some(p) if p.kind == READER_EVENT_NOTIFICATION_DATA => {
                    Self::ReaderEventNotification { data: ReaderEventNotificationData::decode(p)? }
                }
                _ => {
                    return Err(DecodeError(
                        "it carries no ReaderEventNotificationData".to_owned(),
                    ));
                }
            },
            CLOSE_CONNECTION => Self::CloseConnection,
            SET_READER_CONFIG_RESPONSE => {
                Self::SetReaderConfigResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            ADD_ROSPEC_RESPONSE => {
                Self::AddRoSpecResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            DELETE_ROSPEC_RESPONSE => {
                Self::DeleteRoSpecResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            ENABLE_ROSPEC_RESPONSE => {
                Self::EnableRoSpecResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            DISABLE_ROSPEC_RESPONSE => {
                Self::DisableRoSpecResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            START_ROSPEC_RESPONSE => {
                Self::StartRoSpecResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            STOP_ROSPEC_RESPONSE => {
                Self::StopRoSpecResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            ERROR_MESSAGE => Self::ErrorMessage { status: LlrpStatus::first_in(r, &name)? },
            CLOSE_CONNECTION_RESPONSE => {
                Self::CloseConnectionResponse { status: LlrpStatus::first_in(r, &name)? }
            }
            other => Self::Other { kind: other },
        })
    }
}

/// The spec's name of message type `kind`.
pub fn kind_name(kind: u16) -> String {
    use kind::*;
    match kind {
        GET_READER_CAPABILITIES => "GET_READER_CAPABILITIES",
        2 => "GET_READER_CONFIG",
        SET_READER_CONFIG => "SET_READER_CONFIG",
        CLOSE_CONNECTION_RESPONSE => "CLOSE_CONNECTION_RESPONSE",
        GET_READER_CAPABILITIES_RESPONSE => "GET_READER_CAPABILITIES_RESPONSE",
        12 => "GET_READER_CONFIG_RESPONSE",
        SET_READER_CONFIG_RESPONSE => "SET_READER_CONFIG_RESPONSE",
        CLOSE_CONNECTION => "CLOSE_CONNECTION",
        ADD_ROSPEC => "ADD_ROSPEC",
        DELETE_ROSPEC => "DELETE_ROSPEC",
        START_ROSPEC => "START_ROSPEC",
        STOP_ROSPEC => "STOP_ROSPEC",
        ENABLE_ROSPEC => "ENABLE_ROSPEC",
        DISABLE_ROSPEC => "DISABLE_ROSPEC",
        GET_ROSPECS => "GET_ROSPECS",
        ADD_ROSPEC_RESPONSE => "ADD_ROSPEC_RESPONSE",
        DELETE_ROSPEC_RESPONSE => "DELETE_ROSPEC_RESPONSE",
        START_ROSPEC_RESPONSE => "START_ROSPEC_RESPONSE",
        STOP_ROSPEC_RESPONSE => "STOP_ROSPEC_RESPONSE",
        ENABLE_ROSPEC_RESPONSE => "ENABLE_ROSPEC_RESPONSE",
        DISABLE_ROSPEC_RESPONSE => "DISABLE_ROSPEC_RESPONSE",
        GET_ROSPECS_RESPONSE => "GET_ROSPECS_RESPONSE",
        RO_ACCESS_REPORT => "RO_ACCESS_REPORT",
        KEEPALIVE => "KEEPALIVE",
        READER_EVENT_NOTIFICATION => "READER_EVENT_NOTIFICATION",
        KEEPALIVE_ACK => "KEEPALIVE_ACK",
        ERROR_MESSAGE => "ERROR_MESSAGE",
        1023 => "CUSTOM_MESSAGE",
        other => return format!("message type {other}"),
    }
    .to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rfid::llrp::params::capabilities::TransmitPowerLevel;
    use crate::rfid::llrp::params::events::{AntennaEvent, EventTimestamp};
    use crate::rfid::llrp::params::report::{EpcData, FirstSeen};
    use crate::rfid::llrp::params::rospec::*;

    fn refused() -> LlrpStatus {
        LlrpStatus {
            code: 109,
            description: "not today".into(),
            field_error: None,
            parameter_error: None,
        }
    }

    fn rospec() -> RoSpec {
        RoSpec {
            rospec_id: 14,
            priority: 0,
            current_state: RoSpecState::Disabled,
            boundary: RoBoundarySpec {
                start: RoSpecStartTrigger::Null,
                stop: RoSpecStopTrigger::DurationMs(200),
            },
            ai_specs: vec![AiSpec {
                antenna_ids: vec![1, 2],
                stop: AiSpecStopTrigger::DurationMs(200),
                inventory: vec![InventoryParameterSpec {
                    spec_id: 1,
                    protocol_id: 1,
                    antenna_configurations: vec![],
                }],
            }],
            report: None,
        }
    }

    /// One of every message the client knows.
    fn every_message() -> Vec<Message> {
        let mut tag = TagReportData::of(EpcData::from_bytes(&[0x30; 12]));
        tag.antenna_id = Some(2);
        tag.peak_rssi = Some(-47);
        tag.first_seen = Some(FirstSeen::Utc(1));
        let long = TagReportData::of(EpcData::from_bytes(&[0xE2; 16]));
        let mut event = ReaderEventNotificationData::at(EventTimestamp::Utc(7));
        event.antenna = Some(AntennaEvent { connected: false, antenna_id: 3 });
        vec![
            Message::GetReaderCapabilities { requested_data: ALL_CAPABILITIES },
            Message::GetReaderCapabilitiesResponse {
                status: LlrpStatus::success(),
                general: Some(GeneralDeviceCapabilities {
                    max_antennas: 4,
                    can_set_antenna_properties: true,
                    has_utc_clock: true,
                    manufacturer: 25882,
                    model: 700,
                    firmware: "x".into(),
                }),
                regulatory: Some(RegulatoryCapabilities {
                    country_code: 840,
                    communications_standard: 1,
                    transmit_power_levels: vec![TransmitPowerLevel { index: 1, centi_dbm: 1000 }],
                    hopping: false,
                    hop_table_ids: vec![],
                }),
            },
            Message::SetReaderConfig(SetReaderConfig {
                reset_to_factory_default: true,
                event_notifications: Some(ReaderEventNotificationSpec {
                    states: vec![(2, true), (8, true)],
                }),
                keepalive: Some(KeepaliveSpec { period_ms: Some(5000) }),
            }),
            Message::SetReaderConfigResponse { status: LlrpStatus::success() },
            Message::GetRoSpecs,
            Message::GetRoSpecsResponse { status: LlrpStatus::success(), rospecs: vec![rospec()] },
            Message::AddRoSpec { rospec: rospec() },
            Message::AddRoSpecResponse { status: refused() },
            Message::DeleteRoSpec { rospec_id: 14 },
            Message::DeleteRoSpecResponse { status: LlrpStatus::success() },
            Message::EnableRoSpec { rospec_id: 14 },
            Message::EnableRoSpecResponse { status: LlrpStatus::success() },
            Message::DisableRoSpec { rospec_id: 0 },
            Message::DisableRoSpecResponse { status: LlrpStatus::success() },
            Message::StartRoSpec { rospec_id: 14 },
            Message::StartRoSpecResponse { status: LlrpStatus::success() },
            Message::StopRoSpec { rospec_id: 14 },
            Message::StopRoSpecResponse { status: LlrpStatus::success() },
            Message::RoAccessReport { tags: vec![tag, long] },
            Message::RoAccessReport { tags: vec![] },
            Message::Keepalive,
            Message::KeepaliveAck,
            Message::ReaderEventNotification { data: event },
            Message::ErrorMessage { status: refused() },
            Message::CloseConnection,
            Message::CloseConnectionResponse { status: LlrpStatus::success() },
        ]
    }

    #[test]
    fn every_message_round_trips_under_its_id() {
        for (id, message) in every_message().into_iter().enumerate() {
            let bytes = message.encode(id as u32 + 1000);
            assert_eq!(
                Message::decode(&bytes),
                Ok((id as u32 + 1000, message.clone())),
                "{}",
                message.name()
            );
        }
    }

    #[test]
    fn known_bytes_decode_as_the_spec_lays_them_out() {
        // KEEPALIVE, version 1, id 98: 0x04 0x3E, length 10.
        let keepalive = [0x04, 0x3E, 0, 0, 0, 10, 0, 0, 0, 98];
        assert_eq!(Message::decode(&keepalive), Ok((98, Message::Keepalive)));
        assert_eq!(Message::KeepaliveAck.encode(98), [0x04, 0x48, 0, 0, 0, 10, 0, 0, 0, 98]);
        // START_ROSPEC 14.
        assert_eq!(
            Message::StartRoSpec { rospec_id: 14 }.encode(3),
            [0x04, 0x16, 0, 0, 0, 14, 0, 0, 0, 3, 0, 0, 0, 14]
        );
        // A CUSTOM_MESSAGE is not ours, and not an error.
        let custom = message(1023, 5, |out| out.extend_from_slice(&[0, 0, 0x65, 0x1A, 21]));
        assert_eq!(Message::decode(&custom), Ok((5, Message::Other { kind: 1023 })));
    }

    #[test]
    fn a_length_that_disagrees_with_the_bytes_is_an_error() {
        let mut bytes = Message::StartRoSpec { rospec_id: 14 }.encode(3);
        bytes.push(0);
        let err = Message::decode(&bytes).unwrap_err();
        assert_eq!(err.0, "START_ROSPEC says it is 14 bytes long but 15 arrived");
        let err = Message::decode(&bytes[..12]).unwrap_err();
        assert!(err.0.contains("but 12 arrived"), "{err}");
    }
}
