//! What a reader says it is and can do (LLRP 1.0.1 §9.2.1): its antennas, model and firmware,
//! and the transmit power table whose indices an `RFTransmitter` names.

use super::super::wire::{Decoded, FieldReader, Param, tlv, utf8v};

pub const GENERAL_DEVICE_CAPABILITIES: u16 = 137;
pub const REGULATORY_CAPABILITIES: u16 = 143;
const UHF_BAND_CAPABILITIES: u16 = 144;
const TRANSMIT_POWER_LEVEL_TABLE_ENTRY: u16 = 145;
const FREQUENCY_INFORMATION: u16 = 146;
const FREQUENCY_HOP_TABLE: u16 = 147;

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GeneralDeviceCapabilities {
    pub max_antennas: u16,
    pub can_set_antenna_properties: bool,
    pub has_utc_clock: bool,
    /// IANA private enterprise number of the maker (Impinj is 25882).
    pub manufacturer: u32,
    pub model: u32,
    pub firmware: String,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RegulatoryCapabilities {
    /// ISO 3166 numeric country code.
    pub country_code: u16,
    pub communications_standard: u16,
    pub transmit_power_levels: Vec<TransmitPowerLevel>,
    pub hopping: bool,
    pub hop_table_ids: Vec<u8>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TransmitPowerLevel {
    pub index: u16,
    /// Hundredths of a dBm.
    pub centi_dbm: i16,
}

impl GeneralDeviceCapabilities {
    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, GENERAL_DEVICE_CAPABILITIES, |out| {
            out.extend_from_slice(&self.max_antennas.to_be_bytes());
            let flags = (u16::from(self.can_set_antenna_properties) << 15)
                | (u16::from(self.has_utc_clock) << 14);
            out.extend_from_slice(&flags.to_be_bytes());
            out.extend_from_slice(&self.manufacturer.to_be_bytes());
            out.extend_from_slice(&self.model.to_be_bytes());
            utf8v(out, &self.firmware);
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let max_antennas = r.u16("GeneralDeviceCapabilities' antenna count")?;
        let flags = r.u16("GeneralDeviceCapabilities' flags")?;
        Ok(Self {
            max_antennas,
            can_set_antenna_properties: flags & 0x8000 != 0,
            has_utc_clock: flags & 0x4000 != 0,
            manufacturer: r.u32("GeneralDeviceCapabilities' manufacturer")?,
            model: r.u32("GeneralDeviceCapabilities' model")?,
            firmware: r.utf8v("GeneralDeviceCapabilities' firmware version")?,
        })
    }
}

impl RegulatoryCapabilities {
    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, REGULATORY_CAPABILITIES, |out| {
            out.extend_from_slice(&self.country_code.to_be_bytes());
            out.extend_from_slice(&self.communications_standard.to_be_bytes());
            tlv(out, UHF_BAND_CAPABILITIES, |out| {
                for level in &self.transmit_power_levels {
                    tlv(out, TRANSMIT_POWER_LEVEL_TABLE_ENTRY, |out| {
                        out.extend_from_slice(&level.index.to_be_bytes());
                        out.extend_from_slice(&level.centi_dbm.to_be_bytes());
                    });
                }
                tlv(out, FREQUENCY_INFORMATION, |out| {
                    out.push(u8::from(self.hopping) << 7);
                    for id in &self.hop_table_ids {
                        tlv(out, FREQUENCY_HOP_TABLE, |out| {
                            out.extend_from_slice(&[*id, 0, 0, 0]);
                        });
                    }
                });
            });
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let mut caps = Self {
            country_code: r.u16("RegulatoryCapabilities' country code")?,
            communications_standard: r.u16("RegulatoryCapabilities' standard")?,
            transmit_power_levels: Vec::new(),
            hopping: false,
            hop_table_ids: Vec::new(),
        };
        while let Some(p) = r.param()? {
            if p.kind == UHF_BAND_CAPABILITIES {
                caps.decode_uhf_band(&mut p.fields())?;
            }
        }
        Ok(caps)
    }

    fn decode_uhf_band(&mut self, r: &mut FieldReader<'_>) -> Decoded<()> {
        while let Some(p) = r.param()? {
            let mut f = p.fields();
            match p.kind {
                TRANSMIT_POWER_LEVEL_TABLE_ENTRY => {
                    self.transmit_power_levels.push(TransmitPowerLevel {
                        index: f.u16("TransmitPowerLevelTableEntry's index")?,
                        centi_dbm: f.i16("TransmitPowerLevelTableEntry's power")?,
                    })
                }
                FREQUENCY_INFORMATION => {
                    self.hopping = f.u8("FrequencyInformation's hopping flag")? & 0x80 != 0;
                    while let Some(p) = f.param()? {
                        if p.kind == FREQUENCY_HOP_TABLE {
                            self.hop_table_ids.push(p.fields().u8("FrequencyHopTable's id")?);
                        }
                    }
                }
                // The RF mode tables: the reader's default mode is used.
                _ => {}
            }
        }
        Ok(())
    }

    /// The power table's entry nearest `dbm`.
    pub fn nearest_power(&self, dbm: f64) -> Option<TransmitPowerLevel> {
        self.transmit_power_levels.iter().copied().min_by(|a, b| {
            let da = (f64::from(a.centi_dbm) / 100.0 - dbm).abs();
            let db = (f64::from(b.centi_dbm) / 100.0 - dbm).abs();
            da.total_cmp(&db)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capabilities_round_trip_and_the_nearest_power_is_found() {
        let general = GeneralDeviceCapabilities {
            max_antennas: 4,
            can_set_antenna_properties: false,
            has_utc_clock: true,
            manufacturer: 25882,
            model: 700,
            firmware: "8.0.1".into(),
        };
        let regulatory = RegulatoryCapabilities {
            country_code: 840,
            communications_standard: 1,
            transmit_power_levels: (1..=21)
                .map(|i| TransmitPowerLevel { index: i, centi_dbm: 1000 + (i as i16 - 1) * 100 })
                .collect(),
            hopping: true,
            hop_table_ids: vec![1],
        };
        let mut bytes = Vec::new();
        general.encode(&mut bytes);
        regulatory.encode(&mut bytes);
        let mut r = FieldReader::new(&bytes);
        assert_eq!(
            GeneralDeviceCapabilities::decode(r.param().unwrap().unwrap()).unwrap(),
            general
        );
        let decoded = RegulatoryCapabilities::decode(r.param().unwrap().unwrap()).unwrap();
        assert_eq!(decoded, regulatory);
        assert_eq!(decoded.nearest_power(20.4).map(|p| p.index), Some(11));
    }
}
