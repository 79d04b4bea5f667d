//! The reads one inventory round keeps. Every read, up to [`MAX_KEPT`]; past that only the
//! strongest read of each tag on each antenna, for at most [`MAX_KEPT`] of them. A reader that
//! floods — misconfigured, or hostile — costs a bounded amount of memory, never all of it.

use std::collections::HashMap;

use super::params::report::{EpcData, TagReportData};

/// The most reads a round holds. A fixed reader does about a thousand reads a second, so a
/// round of a few hundred milliseconds stays well below it and keeps every read.
pub const MAX_KEPT: usize = 4096;

#[derive(Debug, Default)]
pub struct RoundReads {
    kept: Vec<TagReportData>,
    /// Once the round has more reads than it keeps: where each tag-antenna pair's strongest
    /// read is in `kept`.
    strongest: Option<HashMap<(EpcData, Option<u16>), usize>>,
    /// Every read the reader sent, kept or not.
    seen: u64,
    /// Reads of tag-antenna pairs that found no room.
    dropped: u64,
}

impl RoundReads {
    pub fn add(&mut self, read: TagReportData) {
        self.seen += 1;
        if self.strongest.is_none() {
            if self.kept.len() < MAX_KEPT {
                self.kept.push(read);
                return;
            }
            self.keep_only_the_strongest();
        }
        let index = self.strongest.as_mut().expect("built above");
        match index.get(&(read.epc.clone(), read.antenna_id)) {
            Some(&at) => {
                if read.peak_rssi > self.kept[at].peak_rssi {
                    self.kept[at] = read;
                }
            }
            None if self.kept.len() < MAX_KEPT => {
                index.insert((read.epc.clone(), read.antenna_id), self.kept.len());
                self.kept.push(read);
            }
            None => self.dropped += 1,
        }
    }

    /// How many reads arrived, kept or not.
    pub fn seen(&self) -> u64 {
        self.seen
    }

    /// Whether reads of tags with no room left were dropped: the round saw more different tags
    /// than it can hold.
    pub fn overflowed(&self) -> bool {
        self.dropped > 0
    }

    /// The kept reads; the next round starts empty.
    pub fn take(&mut self) -> Vec<TagReportData> {
        let kept = std::mem::take(&mut self.kept);
        *self = Self::default();
        kept
    }

    fn keep_only_the_strongest(&mut self) {
        // Strongest first within each pair, so keeping each pair's first read keeps its best.
        self.kept.sort_by(|a, b| {
            (&a.epc.bytes, a.epc.bits, a.antenna_id)
                .cmp(&(&b.epc.bytes, b.epc.bits, b.antenna_id))
                .then(b.peak_rssi.cmp(&a.peak_rssi))
        });
        self.kept.dedup_by(|later, first| {
            later.epc == first.epc && later.antenna_id == first.antenna_id
        });
        let index = self
            .kept
            .iter()
            .enumerate()
            .map(|(at, read)| ((read.epc.clone(), read.antenna_id), at))
            .collect();
        self.strongest = Some(index);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(serial: u32, antenna: u16, rssi: i8) -> TagReportData {
        let mut epc = [0x30; 12];
        epc[8..].copy_from_slice(&serial.to_be_bytes());
        TagReportData {
            antenna_id: Some(antenna),
            peak_rssi: Some(rssi),
            ..TagReportData::of(EpcData::from_bytes(&epc))
        }
    }

    #[test]
    fn a_round_below_the_bound_keeps_every_read() {
        let mut round = RoundReads::default();
        for i in 0..100 {
            round.add(read(1, 1, -50 - (i % 7) as i8));
        }
        assert_eq!((round.seen(), round.overflowed()), (100, false));
        assert_eq!(round.take().len(), 100);
        assert_eq!(round.seen(), 0, "the next round starts empty");
    }

    #[test]
    fn past_the_bound_each_tag_and_antenna_keeps_its_strongest_read() {
        let mut round = RoundReads::default();
        for i in 0..100_000u32 {
            let rssi = if i == 77_777 { -40 } else { -55 - (i % 7) as i8 };
            round.add(read(i % 3, 1 + (i % 2) as u16, rssi));
        }
        round.add(read(5, 1, -70));
        let kept = round.take();
        assert_eq!(kept.len(), 7, "three tags on two antennas, and one more tag");
        let best = kept.iter().max_by_key(|r| r.peak_rssi).unwrap();
        assert_eq!((best.peak_rssi, &best.epc), (Some(-40), &read(77_777 % 3, 2, 0).epc));
        let mut others =
            kept.iter().filter(|r| r.epc != read(5, 1, 0).epc && r.peak_rssi != Some(-40));
        assert!(others.clone().count() == 5 && others.all(|r| r.peak_rssi == Some(-55)));
    }

    #[test]
    fn more_different_tags_than_the_bound_are_dropped_and_say_so() {
        let mut round = RoundReads::default();
        for serial in 0..(MAX_KEPT as u32 * 3) {
            round.add(read(serial, 1, -60));
        }
        assert!(round.overflowed());
        assert_eq!(round.seen(), MAX_KEPT as u64 * 3);
        // A tag already kept still gets its stronger read.
        round.add(read(0, 1, -30));
        let kept = round.take();
        assert_eq!(kept.len(), MAX_KEPT);
        assert!(kept.iter().any(|r| r.peak_rssi == Some(-30)));
    }
}
