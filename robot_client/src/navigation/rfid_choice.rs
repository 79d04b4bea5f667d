//! Which tag the fingers are at: the strongest RSSI (paper §IV-A), unless another tag answers
//! almost as strongly, which the paper's 50 cm read range makes possible.

use std::collections::BTreeMap;

use pps_schema::Epc;

use crate::hal::TagRead;

/// One tag's reads, summarised.
#[derive(Debug, Clone, PartialEq)]
pub struct TagSignal {
    pub epc: Epc,
    /// Mean RSSI on the antenna that heard it best, dBm.
    pub rssi_dbm: f64,
    pub reads: usize,
}

/// What the reads say about which tag is in front of the fingers.
#[derive(Debug, Clone, PartialEq)]
pub enum RfidIdentity {
    /// One tag is stronger than every other by at least the margin.
    Identified(TagSignal),
    /// The two strongest are within the margin: re-read closer, or cross-check with where the
    /// tag was seen.
    Ambiguous { strongest: TagSignal, runner_up: TagSignal },
}

impl RfidIdentity {
    pub fn strongest(&self) -> &TagSignal {
        match self {
            Self::Identified(s) | Self::Ambiguous { strongest: s, .. } => s,
        }
    }
}

/// Every tag that answered, strongest first: each tag's reads averaged per antenna (one read
/// is noisy by a few dB), and its best antenna's mean taken.
pub fn tag_signals(reads: &[TagRead]) -> Vec<TagSignal> {
    let mut per_antenna: BTreeMap<(&Epc, u8), (f64, usize)> = BTreeMap::new();
    for read in reads {
        let entry = per_antenna.entry((&read.epc, read.antenna.0)).or_default();
        entry.0 += read.rssi_dbm;
        entry.1 += 1;
    }
    let mut per_tag: BTreeMap<&Epc, TagSignal> = BTreeMap::new();
    for ((epc, _), (sum, n)) in per_antenna {
        let mean = sum / n as f64;
        let signal = per_tag.entry(epc).or_insert(TagSignal {
            epc: epc.clone(),
            rssi_dbm: f64::NEG_INFINITY,
            reads: 0,
        });
        signal.rssi_dbm = signal.rssi_dbm.max(mean);
        signal.reads += n;
    }
    let mut signals: Vec<TagSignal> = per_tag.into_values().collect();
    signals.sort_by(|a, b| b.rssi_dbm.total_cmp(&a.rssi_dbm));
    signals
}

/// Picks the strongest of [`tag_signals`]; `None` when nothing answered.
pub fn identify_tag(reads: &[TagRead], margin_db: f64) -> Option<RfidIdentity> {
    identify_among(tag_signals(reads), margin_db)
}

/// [`identify_tag`] on signals already summarised, strongest first.
pub fn identify_among(signals: Vec<TagSignal>, margin_db: f64) -> Option<RfidIdentity> {
    let mut signals = signals.into_iter();
    let strongest = signals.next()?;
    Some(match signals.next() {
        Some(runner_up) if strongest.rssi_dbm - runner_up.rssi_dbm < margin_db => {
            RfidIdentity::Ambiguous { strongest, runner_up }
        }
        _ => RfidIdentity::Identified(strongest),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hal::AntennaId;

    fn read(epc: &str, rssi_dbm: f64, antenna: u8) -> TagRead {
        TagRead { epc: Epc::parse(epc).unwrap(), rssi_dbm, antenna: AntennaId(antenna) }
    }

    #[test]
    fn strongest_wins_by_a_margin_else_ambiguous() {
        let a = "355AB1C60000001000000001";
        let b = "355AB1C60000002000000001";
        let clear = [read(a, -44.0, 0), read(a, -46.0, 0), read(b, -55.0, 1), read(b, -52.0, 0)];
        let RfidIdentity::Identified(signal) = identify_tag(&clear, 3.0).unwrap() else { panic!() };
        assert_eq!((signal.epc.as_hex(), signal.rssi_dbm, signal.reads), (a, -45.0, 2));
        let close = [read(a, -50.0, 0), read(b, -51.0, 2)];
        assert!(matches!(identify_tag(&close, 3.0), Some(RfidIdentity::Ambiguous { .. })));
        assert_eq!(identify_tag(&[], 3.0), None);
        assert!(matches!(
            identify_tag(&[read(b, -58.0, 3)], 3.0),
            Some(RfidIdentity::Identified(_))
        ));
    }
}
