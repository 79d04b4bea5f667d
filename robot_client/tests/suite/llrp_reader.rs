//! The LLRP client against a reader we did not write: llrpkit's emulator, with each test's own
//! tag population and faults.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use crate::llrpkit::{Emulator, tag};
use pps_robot::hal::{AntennaId, HalError, RfidReader, TagRead};
use pps_robot::navigation::{RfidIdentity, identify_tag};
use pps_robot::rfid::llrp::{LlrpReader, LlrpSettings};
use pps_test_kit::wait_until_blocking;

const LIGHT_SWITCH: &str = "355AB1C60000001000000001";
const LAMP: &str = "355AB1C60000003000000001";
const EPC_128: &str = "E2801160600002084D2AB5C71E0F0A11";

fn settings(emulator: &Emulator, antennas: &[u16], round_ms: u64) -> LlrpSettings {
    LlrpSettings {
        antennas: antennas.to_vec(),
        round: Duration::from_millis(round_ms),
        connect_timeout: Duration::from_secs(2),
        response_timeout: Duration::from_secs(1),
        ..LlrpSettings::new(&emulator.address())
    }
}

fn rounds(reader: &LlrpReader, n: usize) -> Vec<TagRead> {
    (0..n).flat_map(|_| reader.inventory().expect("a round")).collect()
}

fn antennas_of(reads: &[TagRead], epc: &str) -> BTreeSet<u8> {
    reads.iter().filter(|r| r.epc.as_hex() == epc).map(|r| r.antenna.0).collect()
}

#[test]
fn the_strongest_tag_is_chosen_and_a_near_tie_is_ambiguous() {
    let emulator =
        Emulator::start(vec![tag(LIGHT_SWITCH, &[1], -44.0), tag(LAMP, &[2], -58.0)], 400.0);
    let reader = LlrpReader::connect(settings(&emulator, &[1, 2], 150)).unwrap();
    let reads = rounds(&reader, 3);
    assert!(reads.len() > 20, "{} reads in three 150 ms rounds at 400 reads/s", reads.len());
    let Some(RfidIdentity::Identified(chosen)) = identify_tag(&reads, 3.0) else {
        panic!("a 14 dB lead is not ambiguous: {reads:?}")
    };
    assert_eq!(chosen.epc.as_hex(), LIGHT_SWITCH);
    assert!((chosen.rssi_dbm + 44.0).abs() < 1.5, "{} dBm", chosen.rssi_dbm);
    drop(reader);

    let emulator =
        Emulator::start(vec![tag(LIGHT_SWITCH, &[1], -50.0), tag(LAMP, &[1], -51.0)], 400.0);
    let reader = LlrpReader::connect(settings(&emulator, &[1], 150)).unwrap();
    let reads = rounds(&reader, 3);
    assert!(
        matches!(identify_tag(&reads, 3.0), Some(RfidIdentity::Ambiguous { .. })),
        "1 dB apart is within the 3 dB margin"
    );
}

#[test]
fn antenna_numbers_and_epcs_of_96_and_128_bits_are_preserved() {
    let emulator = Emulator::start(
        vec![tag(LIGHT_SWITCH, &[3], -47.0), tag(EPC_128, &[4], -49.0), tag(LAMP, &[1], -40.0)],
        400.0,
    );
    let reader = LlrpReader::connect(settings(&emulator, &[3, 4], 150)).unwrap();
    let reads = rounds(&reader, 3);
    assert_eq!(antennas_of(&reads, LIGHT_SWITCH), BTreeSet::from([3]));
    assert_eq!(antennas_of(&reads, EPC_128), BTreeSet::from([4]));
    assert!(antennas_of(&reads, LAMP).is_empty(), "antenna 1 was not in the round");
    assert!(reads.iter().all(|r| (-56.0..=-40.0).contains(&r.rssi_dbm)), "{reads:?}");
}

#[test]
fn an_antenna_lost_mid_round_keeps_the_others_reads_and_losing_all_is_an_error() {
    let mut emulator =
        Emulator::start(vec![tag(LIGHT_SWITCH, &[1], -45.0), tag(LAMP, &[2], -46.0)], 400.0);
    let reader = LlrpReader::connect(settings(&emulator, &[1, 2], 600)).unwrap();
    assert_eq!(emulator.command("disconnect 2 200"), "ok");
    let during = reader.inventory().expect("the round goes on without antenna 2");
    assert!(!antennas_of(&during, LIGHT_SWITCH).is_empty());
    let after = reader.inventory().expect("antenna 1 still reads");
    assert_eq!(antennas_of(&after, LIGHT_SWITCH), BTreeSet::from([1]));
    assert!(antennas_of(&after, LAMP).is_empty(), "antenna 2 is disconnected: {after:?}");

    assert_eq!(emulator.command("disconnect 1"), "ok");
    let started = Instant::now();
    match reader.inventory() {
        Err(HalError::Unavailable { reason, .. }) => {
            assert!(reason.contains("every antenna of the round disconnected (1, 2)"), "{reason}")
        }
        other => panic!("no antenna left is an error, not {other:?}"),
    }
    assert!(started.elapsed() < Duration::from_secs(3));
    assert_eq!(emulator.command("connect 1"), "ok");
    assert!(!reader.inventory().unwrap().is_empty(), "antenna 1 is back");
}

#[test]
fn a_dropped_request_gives_a_clear_error_or_the_reads_and_the_next_round_works() {
    let mut emulator = Emulator::start(vec![tag(LIGHT_SWITCH, &[1], -45.0)], 400.0);
    let reader = LlrpReader::connect(settings(&emulator, &[1], 150)).unwrap();

    assert_eq!(emulator.command("drop START_ROSPEC"), "ok");
    let started = Instant::now();
    match reader.inventory() {
        Err(HalError::Failed { reason, .. }) => {
            assert!(reason.contains("did not answer START_ROSPEC within 1.0 s"), "{reason}")
        }
        other => panic!("an unanswered START_ROSPEC is an error, not {other:?}"),
    }
    assert!(started.elapsed() < Duration::from_secs(3), "{:?}", started.elapsed());
    assert!(!reader.inventory().unwrap().is_empty(), "the next round reconnects and reads");

    // Without STOP_ROSPEC's answer the round still has its reads.
    assert_eq!(emulator.command("drop STOP_ROSPEC"), "ok");
    let started = Instant::now();
    let reads = reader.inventory().expect("the reads gathered before the stop");
    assert!(!reads.is_empty());
    assert!(started.elapsed() < Duration::from_secs(3), "{:?}", started.elapsed());
    assert!(!reader.inventory().unwrap().is_empty(), "and the round after works too");
}

#[test]
fn keepalives_are_answered_during_a_round() {
    let mut emulator = Emulator::start(vec![tag(LIGHT_SWITCH, &[1], -45.0)], 100.0);
    let reader = LlrpReader::connect(settings(&emulator, &[1], 1200)).unwrap();
    std::thread::scope(|s| {
        let round = s.spawn(|| reader.inventory());
        wait_until_blocking(Duration::from_secs(5), "the round to start", || {
            (emulator.command("active") == "yes").then_some(())
        });
        assert_eq!(emulator.command("keepalive"), "ack");
        assert!(round.join().unwrap().is_ok());
    });
    assert_eq!(emulator.command("acks"), "1");
}

#[test]
fn a_closed_reader_frees_the_emulator_for_the_next_client_at_once() {
    let emulator = Emulator::start(vec![tag(LAMP, &[2], -45.0)], 400.0);
    let first = LlrpReader::connect(settings(&emulator, &[2], 100)).unwrap();
    assert!(!first.inventory().unwrap().is_empty());

    // The emulator takes one controlling client at a time.
    let refused = LlrpReader::connect(LlrpSettings {
        connect_timeout: Duration::from_millis(500),
        ..settings(&emulator, &[2], 100)
    });
    match refused {
        Err(HalError::Unavailable { reason, .. }) => {
            assert!(reason.contains("another client is connected"), "{reason}")
        }
        other => panic!("a second client is refused while the first holds it: {other:?}"),
    }

    drop(first);
    let started = Instant::now();
    let second = LlrpReader::connect(settings(&emulator, &[2], 100)).unwrap();
    assert!(started.elapsed() < Duration::from_secs(1), "{:?}", started.elapsed());
    let reads = second.inventory().unwrap();
    assert!(reads.iter().all(|r| r.antenna == AntennaId(2) && r.epc.as_hex() == LAMP));
}
