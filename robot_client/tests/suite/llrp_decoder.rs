//! The LLRP decoder on bytes no reader should send: random, truncated, or with a lying length.
//! It must never panic, and a refusal must say what it was reading.

use pps_robot::rfid::llrp::messages::Message;
use pps_robot::rfid::llrp::params::report::{EpcData, FirstSeen, TagReportData};
use proptest::prelude::*;

fn tag_report() -> impl Strategy<Value = TagReportData> {
    (
        prop_oneof![
            prop::collection::vec(any::<u8>(), 12).prop_map(|b| EpcData::from_bytes(&b)),
            prop::collection::vec(any::<u8>(), 0..62).prop_map(|b| EpcData::from_bytes(&b)),
        ],
        proptest::option::of(any::<u16>()),
        proptest::option::of(any::<i8>()),
        proptest::option::of(any::<u64>()),
        proptest::option::of(any::<u32>()),
    )
        .prop_map(|(epc, antenna_id, peak_rssi, first_seen, rospec_id)| TagReportData {
            antenna_id,
            peak_rssi,
            first_seen: first_seen.map(FirstSeen::Utc),
            rospec_id,
            ..TagReportData::of(epc)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_decode_or_are_refused_without_panic(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        if let Err(error) = Message::decode(&bytes) {
            prop_assert!(!error.0.is_empty());
        }
    }

    #[test]
    fn random_bodies_under_a_true_header_decode_or_are_refused(kind in 0u16..1024, body in prop::collection::vec(any::<u8>(), 0..200)) {
        let mut bytes = vec![0x04 | (kind >> 8) as u8, kind as u8];
        bytes.extend_from_slice(&((body.len() + 10) as u32).to_be_bytes());
        bytes.extend_from_slice(&1u32.to_be_bytes());
        bytes.extend_from_slice(&body);
        if let Err(error) = Message::decode(&bytes) {
            prop_assert!(!error.0.is_empty());
        }
    }

    #[test]
    fn reports_round_trip_and_every_truncation_is_refused(tags in prop::collection::vec(tag_report(), 0..8), cut in any::<prop::sample::Index>()) {
        let message = Message::RoAccessReport { tags };
        let bytes = message.encode(9);
        prop_assert_eq!(Message::decode(&bytes), Ok((9, message)));
        let short = &bytes[..cut.index(bytes.len())];
        let error = Message::decode(short).expect_err("a truncated message is refused");
        prop_assert!(error.0.contains("arrived") || error.0.contains("header"), "{}", error);
    }

    #[test]
    fn a_report_whose_length_fields_lie_is_refused_or_decoded_never_a_panic(tags in prop::collection::vec(tag_report(), 1..4), at in any::<prop::sample::Index>(), value in any::<u8>()) {
        let mut bytes = Message::RoAccessReport { tags }.encode(9);
        // Corrupt one byte after the header: a parameter's type or length, usually.
        let i = 10 + at.index(bytes.len() - 10);
        bytes[i] = value;
        let _ = Message::decode(&bytes);
    }
}
