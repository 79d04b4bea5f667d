//! `ROSpec` (LLRP 1.0.1 §10.2.1, §16.2.4): the reader operation we ask for — when it starts and
//! stops, which antennas inventory with which settings, and how tags are reported.
//!
//! Only what an inventory round needs is modelled; other parameters inside a reader's own
//! ROSpecs (RF surveys, loop specs, vendors' settings) are skipped on decoding, so a stale spec
//! of any shape can still be listed and deleted.
//!
//! It is long because a ROSpec is one tree of the specification's parameters (eleven nested in
//! it), each kept beside its encoder and decoder in the specification's order, so that the tree
//! reads top to bottom as the specification draws it.

use super::super::wire::{DecodeError, Decoded, FieldReader, Param, tlv};

pub const ROSPEC: u16 = 177;
const RO_BOUNDARY_SPEC: u16 = 178;
const ROSPEC_START_TRIGGER: u16 = 179;
const ROSPEC_STOP_TRIGGER: u16 = 182;
const AI_SPEC: u16 = 183;
const AI_SPEC_STOP_TRIGGER: u16 = 184;
const TAG_OBSERVATION_TRIGGER: u16 = 185;
const INVENTORY_PARAMETER_SPEC: u16 = 186;
const ANTENNA_CONFIGURATION: u16 = 222;
const RF_TRANSMITTER: u16 = 224;
pub const RO_REPORT_SPEC: u16 = 237;
const TAG_REPORT_CONTENT_SELECTOR: u16 = 238;

/// `ProtocolID` of EPCglobal Class 1 Gen 2, the only air protocol LLRP 1.x defines.
pub const EPC_GLOBAL_CLASS1_GEN2: u8 = 1;

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RoSpec {
    pub rospec_id: u32,
    /// 0 is the highest priority.
    pub priority: u8,
    pub current_state: RoSpecState,
    pub boundary: RoBoundarySpec,
    pub ai_specs: Vec<AiSpec>,
    pub report: Option<RoReportSpec>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoSpecState {
    Disabled,
    Inactive,
    Active,
    Unknown(u8),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoBoundarySpec {
    pub start: RoSpecStartTrigger,
    pub stop: RoSpecStopTrigger,
}

/// When the ROSpec starts; periodic and GPI starts decode as `Other`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoSpecStartTrigger {
    /// Only on START_ROSPEC.
    Null,
    Immediate,
    Other(u8),
}

/// When the ROSpec stops; GPI stops decode as `Other`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoSpecStopTrigger {
    /// Only on STOP_ROSPEC, or when its AISpecs are done.
    Null,
    DurationMs(u32),
    Other(u8),
}

/// An antenna inventory: which antennas, until when, with what settings.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AiSpec {
    /// 0 alone means every antenna.
    pub antenna_ids: Vec<u16>,
    pub stop: AiSpecStopTrigger,
    pub inventory: Vec<InventoryParameterSpec>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AiSpecStopTrigger {
    /// When the ROSpec ends.
    Null,
    DurationMs(u32),
    /// `TagObservationTrigger` type 0: upon seeing N tag reads, or at the timeout.
    TagsOrTimeout {
        tags: u16,
        timeout_ms: u32,
    },
    Other(u8),
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InventoryParameterSpec {
    pub spec_id: u16,
    pub protocol_id: u8,
    pub antenna_configurations: Vec<AntennaConfiguration>,
}

/// One antenna's settings for the inventory; only transmit power is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AntennaConfiguration {
    pub antenna_id: u16,
    pub transmitter: Option<RfTransmitter>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RfTransmitter {
    pub hop_table_id: u16,
    pub channel_index: u16,
    /// An index into the reader's transmit power table (its capabilities), not dBm.
    pub transmit_power: u16,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoReportSpec {
    pub trigger: RoReportTrigger,
    /// Tag reports per RO_ACCESS_REPORT; 0 means no limit (report at the trigger's end only).
    pub n: u16,
    pub content: TagReportContentSelector,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoReportTrigger {
    None,
    UponNOrEndOfAiSpec,
    UponNOrEndOfRoSpec,
    Other(u8),
}

/// Which optional fields each TagReportData carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TagReportContentSelector {
    pub rospec_id: bool,
    pub spec_index: bool,
    pub inventory_parameter_spec_id: bool,
    pub antenna_id: bool,
    pub channel_index: bool,
    pub peak_rssi: bool,
    pub first_seen_timestamp: bool,
    pub last_seen_timestamp: bool,
    pub tag_seen_count: bool,
    pub access_spec_id: bool,
}

impl RoSpecState {
    fn code(self) -> u8 {
        match self {
            Self::Disabled => 0,
            Self::Inactive => 1,
            Self::Active => 2,
            Self::Unknown(code) => code,
        }
    }

    fn from_code(code: u8) -> Self {
        match code {
            0 => Self::Disabled,
            1 => Self::Inactive,
            2 => Self::Active,
            other => Self::Unknown(other),
        }
    }
}

impl RoSpec {
    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, ROSPEC, |out| {
            out.extend_from_slice(&self.rospec_id.to_be_bytes());
            out.push(self.priority);
            out.push(self.current_state.code());
            self.boundary.encode(out);
            for spec in &self.ai_specs {
                spec.encode(out);
            }
            if let Some(report) = &self.report {
                report.encode(out);
            }
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let rospec_id = r.u32("ROSpec's ROSpecID")?;
        let priority = r.u8("ROSpec's priority")?;
        let current_state = RoSpecState::from_code(r.u8("ROSpec's current state")?);
        let mut boundary = None;
        let mut ai_specs = Vec::new();
        let mut report = None;
        while let Some(p) = r.param()? {
            match p.kind {
                RO_BOUNDARY_SPEC => boundary = Some(RoBoundarySpec::decode(p)?),
                AI_SPEC => ai_specs.push(AiSpec::decode(p)?),
                RO_REPORT_SPEC => report = Some(RoReportSpec::decode(p)?),
                _ => {}
            }
        }
        let boundary = boundary
            .ok_or_else(|| DecodeError(format!("ROSpec {rospec_id} has no ROBoundarySpec")))?;
        Ok(Self { rospec_id, priority, current_state, boundary, ai_specs, report })
    }
}

impl RoBoundarySpec {
    fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, RO_BOUNDARY_SPEC, |out| {
            tlv(out, ROSPEC_START_TRIGGER, |out| {
                out.push(match self.start {
                    RoSpecStartTrigger::Null => 0,
                    RoSpecStartTrigger::Immediate => 1,
                    RoSpecStartTrigger::Other(code) => code,
                })
            });
            tlv(out, ROSPEC_STOP_TRIGGER, |out| {
                let (kind, ms) = match self.stop {
                    RoSpecStopTrigger::Null => (0, 0),
                    RoSpecStopTrigger::DurationMs(ms) => (1, ms),
                    RoSpecStopTrigger::Other(code) => (code, 0),
                };
                out.push(kind);
                out.extend_from_slice(&ms.to_be_bytes());
            });
        });
    }

    fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let mut start = None;
        let mut stop = None;
        while let Some(p) = r.param()? {
            let mut f = p.fields();
            match p.kind {
                ROSPEC_START_TRIGGER => {
                    start = Some(match f.u8("ROSpecStartTrigger's type")? {
                        0 => RoSpecStartTrigger::Null,
                        1 => RoSpecStartTrigger::Immediate,
                        other => RoSpecStartTrigger::Other(other),
                    })
                }
                ROSPEC_STOP_TRIGGER => {
                    let kind = f.u8("ROSpecStopTrigger's type")?;
                    let ms = f.u32("ROSpecStopTrigger's duration")?;
                    stop = Some(match kind {
                        0 => RoSpecStopTrigger::Null,
                        1 => RoSpecStopTrigger::DurationMs(ms),
                        other => RoSpecStopTrigger::Other(other),
                    })
                }
                _ => {}
            }
        }
        match (start, stop) {
            (Some(start), Some(stop)) => Ok(Self { start, stop }),
            _ => Err(DecodeError("ROBoundarySpec lacks its start or stop trigger".to_owned())),
        }
    }
}

impl AiSpec {
    fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, AI_SPEC, |out| {
            out.extend_from_slice(&(self.antenna_ids.len() as u16).to_be_bytes());
            for id in &self.antenna_ids {
                out.extend_from_slice(&id.to_be_bytes());
            }
            tlv(out, AI_SPEC_STOP_TRIGGER, |out| {
                let (kind, ms) = match self.stop {
                    AiSpecStopTrigger::Null => (0, 0),
                    AiSpecStopTrigger::DurationMs(ms) => (1, ms),
                    AiSpecStopTrigger::TagsOrTimeout { .. } => (3, 0),
                    AiSpecStopTrigger::Other(code) => (code, 0),
                };
                out.push(kind);
                out.extend_from_slice(&ms.to_be_bytes());
                if let AiSpecStopTrigger::TagsOrTimeout { tags, timeout_ms } = self.stop {
                    tlv(out, TAG_OBSERVATION_TRIGGER, |out| {
                        out.push(0); // upon seeing N tags, or the timeout
                        out.push(0);
                        out.extend_from_slice(&tags.to_be_bytes());
                        out.extend_from_slice(&0u16.to_be_bytes()); // attempts
                        out.extend_from_slice(&0u16.to_be_bytes()); // T, ms
                        out.extend_from_slice(&timeout_ms.to_be_bytes());
                    });
                }
            });
            for spec in &self.inventory {
                spec.encode(out);
            }
        });
    }

    fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let count = r.u16("AISpec's antenna count")? as usize;
        let mut antenna_ids = Vec::with_capacity(count.min(r.remaining() / 2));
        for _ in 0..count {
            antenna_ids.push(r.u16("AISpec's antenna ids")?);
        }
        let mut stop = None;
        let mut inventory = Vec::new();
        while let Some(p) = r.param()? {
            match p.kind {
                AI_SPEC_STOP_TRIGGER => stop = Some(decode_ai_stop(p)?),
                INVENTORY_PARAMETER_SPEC => inventory.push(InventoryParameterSpec::decode(p)?),
                _ => {}
            }
        }
        let stop = stop.ok_or_else(|| DecodeError("AISpec has no AISpecStopTrigger".to_owned()))?;
        Ok(Self { antenna_ids, stop, inventory })
    }
}

fn decode_ai_stop(param: Param<'_>) -> Decoded<AiSpecStopTrigger> {
    let mut f = param.fields();
    let kind = f.u8("AISpecStopTrigger's type")?;
    let ms = f.u32("AISpecStopTrigger's duration")?;
    Ok(match kind {
        0 => AiSpecStopTrigger::Null,
        1 => AiSpecStopTrigger::DurationMs(ms),
        3 => {
            let mut observation = None;
            while let Some(p) = f.param()? {
                if p.kind == TAG_OBSERVATION_TRIGGER {
                    let mut t = p.fields();
                    let trigger = t.u8("TagObservationTrigger's type")?;
                    t.u8("TagObservationTrigger's reserved byte")?;
                    let tags = t.u16("TagObservationTrigger's number of tags")?;
                    t.u16("TagObservationTrigger's number of attempts")?;
                    t.u16("TagObservationTrigger's T")?;
                    let timeout_ms = t.u32("TagObservationTrigger's timeout")?;
                    observation = Some((trigger, tags, timeout_ms));
                }
            }
            match observation {
                Some((0, tags, timeout_ms)) => {
                    AiSpecStopTrigger::TagsOrTimeout { tags, timeout_ms }
                }
                _ => AiSpecStopTrigger::Other(kind),
            }
        }
        other => AiSpecStopTrigger::Other(other),
    })
}

impl InventoryParameterSpec {
    fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, INVENTORY_PARAMETER_SPEC, |out| {
            out.extend_from_slice(&self.spec_id.to_be_bytes());
            out.push(self.protocol_id);
            for config in &self.antenna_configurations {
                tlv(out, ANTENNA_CONFIGURATION, |out| {
                    out.extend_from_slice(&config.antenna_id.to_be_bytes());
                    if let Some(t) = config.transmitter {
                        tlv(out, RF_TRANSMITTER, |out| {
                            out.extend_from_slice(&t.hop_table_id.to_be_bytes());
                            out.extend_from_slice(&t.channel_index.to_be_bytes());
                            out.extend_from_slice(&t.transmit_power.to_be_bytes());
                        });
                    }
                });
            }
        });
    }

    fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let spec_id = r.u16("InventoryParameterSpec's id")?;
        let protocol_id = r.u8("InventoryParameterSpec's protocol")?;
        let mut antenna_configurations = Vec::new();
        while let Some(p) = r.param()? {
            if p.kind != ANTENNA_CONFIGURATION {
                continue;
            }
            let mut a = p.fields();
            let mut config = AntennaConfiguration {
                antenna_id: a.u16("AntennaConfiguration's AntennaID")?,
                transmitter: None,
            };
            while let Some(p) = a.param()? {
                if p.kind == RF_TRANSMITTER {
                    let mut t = p.fields();
                    config.transmitter = Some(RfTransmitter {
                        hop_table_id: t.u16("RFTransmitter's hop table")?,
                        channel_index: t.u16("RFTransmitter's channel")?,
                        transmit_power: t.u16("RFTransmitter's power index")?,
                    });
                }
            }
            antenna_configurations.push(config);
        }
        Ok(Self { spec_id, protocol_id, antenna_configurations })
    }
}

impl RoReportSpec {
    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, RO_REPORT_SPEC, |out| {
            out.push(match self.trigger {
                RoReportTrigger::None => 0,
                RoReportTrigger::UponNOrEndOfAiSpec => 1,
                RoReportTrigger::UponNOrEndOfRoSpec => 2,
                RoReportTrigger::Other(code) => code,
            });
            out.extend_from_slice(&self.n.to_be_bytes());
            tlv(out, TAG_REPORT_CONTENT_SELECTOR, |out| {
                out.extend_from_slice(&self.content.bits().to_be_bytes())
            });
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let trigger = match r.u8("ROReportSpec's trigger")? {
            0 => RoReportTrigger::None,
            1 => RoReportTrigger::UponNOrEndOfAiSpec,
            2 => RoReportTrigger::UponNOrEndOfRoSpec,
            other => RoReportTrigger::Other(other),
        };
        let n = r.u16("ROReportSpec's N")?;
        let mut content = None;
        while let Some(p) = r.param()? {
            if p.kind == TAG_REPORT_CONTENT_SELECTOR {
                content = Some(TagReportContentSelector::from_bits(
                    p.fields().u16("TagReportContentSelector")?,
                ));
            }
        }
        let content = content.ok_or_else(|| {
            DecodeError("ROReportSpec has no TagReportContentSelector".to_owned())
        })?;
        Ok(Self { trigger, n, content })
    }
}

impl TagReportContentSelector {
    fn flags(&self) -> [bool; 10] {
        [
            self.rospec_id,
            self.spec_index,
            self.inventory_parameter_spec_id,
            self.antenna_id,
            self.channel_index,
            self.peak_rssi,
            self.first_seen_timestamp,
            self.last_seen_timestamp,
            self.tag_seen_count,
            self.access_spec_id,
        ]
    }

    /// The flags from the top bit down, in the spec's order; the low 6 bits are reserved.
    fn bits(&self) -> u16 {
        self.flags().iter().enumerate().fold(0, |bits, (i, &on)| bits | (u16::from(on) << (15 - i)))
    }

    fn from_bits(bits: u16) -> Self {
        let on = |i: u16| bits & (1 << (15 - i)) != 0;
        Self {
            rospec_id: on(0),
            spec_index: on(1),
            inventory_parameter_spec_id: on(2),
            antenna_id: on(3),
            channel_index: on(4),
            peak_rssi: on(5),
            first_seen_timestamp: on(6),
            last_seen_timestamp: on(7),
            tag_seen_count: on(8),
            access_spec_id: on(9),
        }
    }
}

/// The ROSpec ids in a list of parameters (GET_ROSPECS_RESPONSE's body after its status).
pub fn decode_rospecs(r: &mut FieldReader<'_>) -> Decoded<Vec<RoSpec>> {
    let mut specs = Vec::new();
    while let Some(p) = r.param()? {
        if p.kind == ROSPEC {
            specs.push(RoSpec::decode(p)?);
        }
    }
    Ok(specs)
}

#[cfg(test)]
mod tests {
    use super::*;

    pub fn inventory_rospec() -> RoSpec {
        RoSpec {
            rospec_id: 14,
            priority: 0,
            current_state: RoSpecState::Disabled,
            boundary: RoBoundarySpec {
                start: RoSpecStartTrigger::Null,
                stop: RoSpecStopTrigger::DurationMs(250),
            },
            ai_specs: vec![AiSpec {
                antenna_ids: vec![1, 3],
                stop: AiSpecStopTrigger::TagsOrTimeout { tags: 40, timeout_ms: 250 },
                inventory: vec![InventoryParameterSpec {
                    spec_id: 1,
                    protocol_id: EPC_GLOBAL_CLASS1_GEN2,
                    antenna_configurations: vec![AntennaConfiguration {
                        antenna_id: 1,
                        transmitter: Some(RfTransmitter {
                            hop_table_id: 1,
                            channel_index: 1,
                            transmit_power: 81,
                        }),
                    }],
                }],
            }],
            report: Some(RoReportSpec {
                trigger: RoReportTrigger::UponNOrEndOfRoSpec,
                n: 1,
                content: TagReportContentSelector {
                    antenna_id: true,
                    peak_rssi: true,
                    first_seen_timestamp: true,
                    ..TagReportContentSelector::default()
                },
            }),
        }
    }

    #[test]
    fn an_inventory_rospec_round_trips() {
        for stop in [
            AiSpecStopTrigger::DurationMs(300),
            AiSpecStopTrigger::Null,
            AiSpecStopTrigger::TagsOrTimeout { tags: 40, timeout_ms: 250 },
        ] {
            let mut spec = inventory_rospec();
            spec.ai_specs[0].stop = stop;
            let mut bytes = Vec::new();
            spec.encode(&mut bytes);
            let mut r = FieldReader::new(&bytes);
            assert_eq!(decode_rospecs(&mut r).unwrap(), vec![spec]);
        }
    }

    #[test]
    fn content_selector_bits_are_in_the_spec_order() {
        let only_antenna = TagReportContentSelector { antenna_id: true, ..Default::default() };
        assert_eq!(only_antenna.bits(), 0x1000);
        let all = TagReportContentSelector::from_bits(0xFFC0);
        assert_eq!(all.bits(), 0xFFC0);
    }
}
