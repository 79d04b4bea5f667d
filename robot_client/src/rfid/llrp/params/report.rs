//! `TagReportData` (LLRP 1.0.1 §13.2.3): one tag's read, with the optional fields the ROSpec's
//! report spec asked for. The hot path of the client: a busy reader sends thousands a second,
//! so decoding allocates only the EPC.

use super::super::wire::{DecodeError, Decoded, FieldReader, Param, tlv, tv};

pub const TAG_REPORT_DATA: u16 = 240;
const EPC_DATA: u16 = 241;
const TV_ANTENNA_ID: u8 = 1;
const TV_FIRST_SEEN_UTC: u8 = 2;
const TV_FIRST_SEEN_UPTIME: u8 = 3;
const TV_LAST_SEEN_UTC: u8 = 4;
const TV_LAST_SEEN_UPTIME: u8 = 5;
const TV_PEAK_RSSI: u8 = 6;
const TV_CHANNEL_INDEX: u8 = 7;
const TV_TAG_SEEN_COUNT: u8 = 8;
const TV_ROSPEC_ID: u8 = 9;
const TV_INVENTORY_PARAMETER_SPEC_ID: u8 = 10;
const TV_C1G2_CRC: u8 = 11;
const TV_C1G2_PC: u8 = 12;
const TV_EPC_96: u8 = 13;
const TV_SPEC_INDEX: u8 = 14;
const TV_ACCESS_SPEC_ID: u8 = 16;

/// A tag's EPC as the reader sent it: `EPC-96` or `EPCData` of any bit length.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct EpcData {
    /// Length in bits; the bytes hold it, padded with zero bits at the end.
    pub bits: u16,
    pub bytes: Vec<u8>,
}

/// When the reader first saw the tag in this report's period, microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FirstSeen {
    /// Since 1970-01-01 UTC.
    Utc(u64),
    /// Since the reader booted.
    Uptime(u64),
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TagReportData {
    pub epc: EpcData,
    pub rospec_id: Option<u32>,
    pub spec_index: Option<u16>,
    pub inventory_parameter_spec_id: Option<u16>,
    pub antenna_id: Option<u16>,
    /// dBm.
    pub peak_rssi: Option<i8>,
    pub channel_index: Option<u16>,
    pub first_seen: Option<FirstSeen>,
    pub last_seen: Option<FirstSeen>,
    pub tag_seen_count: Option<u16>,
    pub access_spec_id: Option<u32>,
    /// The tag's Gen2 protocol-control word and CRC, when the reader reports them.
    pub pc_bits: Option<u16>,
    pub crc: Option<u16>,
}

impl EpcData {
    pub fn from_bytes(bytes: &[u8]) -> Self {
        Self { bits: (bytes.len() * 8) as u16, bytes: bytes.to_vec() }
    }

    /// Upper-case hex of the EPC's bits (whole bytes).
    pub fn to_hex(&self) -> String {
        use std::fmt::Write;
        self.bytes.iter().fold(String::with_capacity(self.bytes.len() * 2), |mut s, b| {
            let _ = write!(s, "{b:02X}");
            s
        })
    }
}

impl TagReportData {
    /// A report of `epc` carrying nothing else; set the optional fields after.
    pub fn of(epc: EpcData) -> Self {
        Self {
            epc,
            rospec_id: None,
            spec_index: None,
            inventory_parameter_spec_id: None,
            antenna_id: None,
            peak_rssi: None,
            channel_index: None,
            first_seen: None,
            last_seen: None,
            tag_seen_count: None,
            access_spec_id: None,
            pc_bits: None,
            crc: None,
        }
    }

    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, TAG_REPORT_DATA, |out| {
            // Readers send a 96-bit EPC as the compact TV form; we do as they do.
            if self.epc.bits == 96 && self.epc.bytes.len() == 12 {
                tv(out, TV_EPC_96);
                out.extend_from_slice(&self.epc.bytes);
            } else {
                tlv(out, EPC_DATA, |out| {
                    out.extend_from_slice(&self.epc.bits.to_be_bytes());
                    out.extend_from_slice(&self.epc.bytes);
                });
            }
            let mut field = |kind: u8, value: &[u8]| {
                tv(out, kind);
                out.extend_from_slice(value);
            };
            if let Some(v) = self.rospec_id {
                field(TV_ROSPEC_ID, &v.to_be_bytes());
            }
            if let Some(v) = self.spec_index {
                field(TV_SPEC_INDEX, &v.to_be_bytes());
            }
            if let Some(v) = self.inventory_parameter_spec_id {
                field(TV_INVENTORY_PARAMETER_SPEC_ID, &v.to_be_bytes());
            }
            if let Some(v) = self.antenna_id {
                field(TV_ANTENNA_ID, &v.to_be_bytes());
            }
            if let Some(v) = self.peak_rssi {
                field(TV_PEAK_RSSI, &v.to_be_bytes());
            }
            if let Some(v) = self.channel_index {
                field(TV_CHANNEL_INDEX, &v.to_be_bytes());
            }
            match self.first_seen {
                Some(FirstSeen::Utc(us)) => field(TV_FIRST_SEEN_UTC, &us.to_be_bytes()),
                Some(FirstSeen::Uptime(us)) => field(TV_FIRST_SEEN_UPTIME, &us.to_be_bytes()),
                None => {}
            }
            match self.last_seen {
                Some(FirstSeen::Utc(us)) => field(TV_LAST_SEEN_UTC, &us.to_be_bytes()),
                Some(FirstSeen::Uptime(us)) => field(TV_LAST_SEEN_UPTIME, &us.to_be_bytes()),
                None => {}
            }
            if let Some(v) = self.tag_seen_count {
                field(TV_TAG_SEEN_COUNT, &v.to_be_bytes());
            }
            if let Some(v) = self.pc_bits {
                field(TV_C1G2_PC, &v.to_be_bytes());
            }
            if let Some(v) = self.crc {
                field(TV_C1G2_CRC, &v.to_be_bytes());
            }
            if let Some(v) = self.access_spec_id {
                field(TV_ACCESS_SPEC_ID, &v.to_be_bytes());
            }
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let mut report = Self::of(EpcData { bits: 0, bytes: Vec::new() });
        let mut has_epc = false;
        while let Some(p) = r.param()? {
            let mut f = p.fields();
            if !p.tv {
                if p.kind == EPC_DATA {
                    let bits = f.u16("EPCData's bit length")?;
                    let bytes = f.take((bits as usize).div_ceil(8), "EPCData's EPC")?;
                    report.epc = EpcData { bits, bytes: bytes.to_vec() };
                    has_epc = true;
                }
                // Air-protocol tag data, op-spec results and vendors' parameters: not ours.
                continue;
            }
            match p.kind as u8 {
                TV_EPC_96 => {
                    report.epc = EpcData { bits: 96, bytes: p.body.to_vec() };
                    has_epc = true;
                }
                TV_ANTENNA_ID => report.antenna_id = Some(f.u16("AntennaID")?),
                TV_PEAK_RSSI => report.peak_rssi = Some(f.i8("PeakRSSI")?),
                TV_FIRST_SEEN_UTC => {
                    report.first_seen = Some(FirstSeen::Utc(f.u64("FirstSeenTimestampUTC")?))
                }
                TV_FIRST_SEEN_UPTIME => {
                    report.first_seen = Some(FirstSeen::Uptime(f.u64("FirstSeenTimestampUptime")?))
                }
                TV_LAST_SEEN_UTC => {
                    report.last_seen = Some(FirstSeen::Utc(f.u64("LastSeenTimestampUTC")?))
                }
                TV_LAST_SEEN_UPTIME => {
                    report.last_seen = Some(FirstSeen::Uptime(f.u64("LastSeenTimestampUptime")?))
                }
                TV_CHANNEL_INDEX => report.channel_index = Some(f.u16("ChannelIndex")?),
                TV_TAG_SEEN_COUNT => report.tag_seen_count = Some(f.u16("TagSeenCount")?),
                TV_ROSPEC_ID => report.rospec_id = Some(f.u32("ROSpecID")?),
                TV_SPEC_INDEX => report.spec_index = Some(f.u16("SpecIndex")?),
                TV_INVENTORY_PARAMETER_SPEC_ID => {
                    report.inventory_parameter_spec_id = Some(f.u16("InventoryParameterSpecID")?)
                }
                TV_C1G2_PC => report.pc_bits = Some(f.u16("C1G2-PC")?),
                TV_C1G2_CRC => report.crc = Some(f.u16("C1G2-CRC")?),
                TV_ACCESS_SPEC_ID => report.access_spec_id = Some(f.u32("AccessSpecID")?),
                _ => {}
            }
        }
        if !has_epc {
            return Err(DecodeError("a TagReportData carries no EPC".to_owned()));
        }
        Ok(report)
    }
}

/// The tag reports in an RO_ACCESS_REPORT body (RF survey data and vendors' parameters are
/// skipped).
pub fn decode_tag_reports(r: &mut FieldReader<'_>, into: &mut Vec<TagReportData>) -> Decoded<()> {
    for_each_tag_report(r, |report| into.push(report))
}

/// Each tag report in an RO_ACCESS_REPORT body, handed to `each` as it is decoded, so a report
/// of a million tags is never held decoded all at once. Reports before a bad one are handed on.
pub fn for_each_tag_report(
    r: &mut FieldReader<'_>,
    mut each: impl FnMut(TagReportData),
) -> Decoded<()> {
    while let Some(p) = r.param()? {
        if p.kind == TAG_REPORT_DATA && !p.tv {
            each(TagReportData::decode(p)?);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(report: &TagReportData) -> TagReportData {
        let mut bytes = Vec::new();
        report.encode(&mut bytes);
        let mut out = Vec::new();
        decode_tag_reports(&mut FieldReader::new(&bytes), &mut out).unwrap();
        assert_eq!(out.len(), 1);
        out.remove(0)
    }

    #[test]
    fn epcs_of_96_128_and_odd_lengths_round_trip_with_every_field() {
        let mut full = TagReportData::of(EpcData::from_bytes(&[0xE2; 16]));
        full.rospec_id = Some(14);
        full.spec_index = Some(1);
        full.inventory_parameter_spec_id = Some(1);
        full.antenna_id = Some(3);
        full.peak_rssi = Some(-52);
        full.channel_index = Some(7);
        full.first_seen = Some(FirstSeen::Utc(1_764_000_000_123_456));
        full.last_seen = Some(FirstSeen::Uptime(99));
        full.tag_seen_count = Some(4);
        full.access_spec_id = Some(0);
        full.pc_bits = Some(0x4000);
        full.crc = Some(0xBEEF);
        assert_eq!(round_trip(&full), full);
        let epc96 = TagReportData::of(EpcData::from_bytes(&[0x35; 12]));
        assert_eq!(round_trip(&epc96), epc96);
        // 100 bits travel in 13 bytes.
        let odd = TagReportData::of(EpcData { bits: 100, bytes: vec![0xAB; 13] });
        assert_eq!(round_trip(&odd), odd);
        assert_eq!(EpcData::from_bytes(&[0x30, 0x0a]).to_hex(), "300A");
    }

    #[test]
    fn an_epc_data_longer_than_its_parameter_is_an_error() {
        let mut bytes = Vec::new();
        tlv(&mut bytes, TAG_REPORT_DATA, |out| {
            tlv(out, EPC_DATA, |out| {
                out.extend_from_slice(&128u16.to_be_bytes());
                out.extend_from_slice(&[0; 8]);
            })
        });
        let err = decode_tag_reports(&mut FieldReader::new(&bytes), &mut Vec::new()).unwrap_err();
        assert!(err.0.contains("EPCData's EPC needs 16 bytes"), "{err}");
    }
}
