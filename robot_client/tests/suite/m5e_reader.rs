//! The M5e client against a peer on the other end of a pseudo-terminal that answers as a
//! module does, frame by frame, or fails to: a bad CRC, a short frame, no answer.

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use pps_robot::hal::{AntennaId, HalError, RfidReader};
use pps_robot::rfid::m5e::frame::{crc16, response};
use pps_robot::rfid::m5e::{M5eReader, M5eSettings};
use serialport::{SerialPort, TTYPort};

const LAMP: &str = "355AB1C60000003000000001";
const EPC_128: &str = "E2801160600002084D2AB5C71E0F0A11";

/// A command as the peer received it: opcode and data.
type Command = (u8, Vec<u8>);

/// What the peer does with one command.
enum Answer {
    Frame(Vec<u8>),
    Silence,
}

/// The module's side: parses each command frame (checking its CRC, as a module does) and
/// answers as `answer` says; every command it received is kept.
struct Peer {
    commands: Arc<Mutex<Vec<Command>>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Peer {
    fn start(mut port: TTYPort, answer: impl Fn(u8, &[u8]) -> Answer + Send + 'static) -> Self {
        let commands = Arc::new(Mutex::new(Vec::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let (seen, stopping) = (commands.clone(), stop.clone());
        port.set_timeout(Duration::from_millis(20)).unwrap();
        let thread = std::thread::spawn(move || {
            let mut pending = Vec::new();
            while !stopping.load(Ordering::Relaxed) {
                let mut chunk = [0u8; 256];
                if let Ok(n) = port.read(&mut chunk) {
                    pending.extend_from_slice(&chunk[..n]);
                }
                while pending.len() >= 5 && pending.len() >= usize::from(pending[1]) + 5 {
                    let len = usize::from(pending[1]) + 5;
                    let frame: Vec<u8> = pending.drain(..len).collect();
                    assert_eq!(frame[0], 0xFF, "a command starts with 0xFF");
                    let crc = u16::from_be_bytes([frame[len - 2], frame[len - 1]]);
                    assert_eq!(crc, crc16(&frame[1..len - 2]), "the command's CRC");
                    let (op, data) = (frame[2], frame[3..len - 2].to_vec());
                    seen.lock().unwrap().push((op, data.clone()));
                    if let Answer::Frame(bytes) = answer(op, &data) {
                        port.write_all(&bytes).unwrap();
                    }
                }
            }
        });
        Self { commands, stop, thread: Some(thread) }
    }

    fn commands(&self) -> Vec<Command> {
        self.commands.lock().unwrap().clone()
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// One get-tag-buffer record with read count, RSSI and antenna, then PC, EPC and a CRC.
fn record(epc: &str, reads: u8, rssi: i8, antenna: u8) -> Vec<u8> {
    let epc = hex::decode(epc).unwrap();
    let mut out = vec![reads, rssi as u8, antenna];
    out.extend_from_slice(&(((epc.len() + 4) * 8) as u16).to_be_bytes());
    out.extend_from_slice(&[0x30, 0x00]);
    out.extend_from_slice(&epc);
    out.extend_from_slice(&[0xAB, 0xCD]);
    out
}

/// A module that sets up and finds the lamp's tag twice on antenna 1 and a 128-bit EPC on 2.
fn healthy(op: u8, _data: &[u8]) -> Answer {
    Answer::Frame(match op {
        0x03 => response(op, 0, &[0x12, 0x06, 0x26, 0x00, 0x01, 0x02, 0x00, 0x00]),
        0x22 => response(op, 0, &[0x00, 0x00, 0x01, 2]),
        0x29 => {
            let mut data = vec![0x00, 0x07, 0x00, 2];
            data.extend(record(LAMP, 2, -45, 1));
            data.extend(record(EPC_128, 1, -60, 2));
            response(op, 0, &data)
        }
        _ => response(op, 0, &[]),
    })
}

fn settings() -> M5eSettings {
    M5eSettings {
        antennas: vec![1, 2],
        read_power_dbm: Some(20.0),
        round: Duration::from_millis(50),
        response_timeout: Duration::from_millis(300),
        ..M5eSettings::new("pty")
    }
}

fn reader_with(
    answer: impl Fn(u8, &[u8]) -> Answer + Send + 'static,
) -> (Result<M5eReader, HalError>, Peer) {
    let (ours, theirs) = TTYPort::pair().expect("a pseudo-terminal");
    let peer = Peer::start(theirs, answer);
    let port: Box<dyn SerialPort> = Box::new(ours);
    (M5eReader::on_port(settings(), port), peer)
}

fn failure(result: Result<impl std::fmt::Debug, HalError>) -> String {
    match result {
        Err(HalError::Failed { reason, .. }) => reason,
        other => panic!("expected a failure, got {other:?}"),
    }
}

#[test]
fn set_up_then_a_round_gives_each_tag_with_rssi_and_antenna() {
    let (reader, peer) = reader_with(healthy);
    let reader = reader.unwrap();
    assert_eq!(reader.version, "12 06 26 00 01 02 00 00");
    let reads = reader.inventory().unwrap();
    let summary: Vec<_> = reads.iter().map(|r| (r.epc.as_hex(), r.rssi_dbm, r.antenna)).collect();
    assert_eq!(
        summary,
        [(LAMP, -45.0, AntennaId(1)), (LAMP, -45.0, AntennaId(1)), (EPC_128, -60.0, AntennaId(2)),]
    );
    let ops: Vec<Command> = peer.commands();
    assert_eq!(
        ops,
        [
            (0x03, vec![]),
            (0x97, vec![0x01]),             // North America
            (0x93, vec![0x00, 0x05]),       // Gen2
            (0x92, vec![0x07, 0xD0]),       // 20.00 dBm
            (0x91, vec![0x02, 1, 1, 2, 2]), // both ports, each transmitting and receiving
            (0x2A, vec![]),
            (0x22, vec![0x00, 0x00, 0x01, 0x00, 50]),
            (0x29, vec![0x00, 0x07, 0x00]),
        ]
    );
}

#[test]
fn no_tag_found_is_an_empty_round_not_an_error() {
    let (reader, _peer) = reader_with(|op, data| match op {
        0x22 => Answer::Frame(response(op, 0x0400, &[])),
        _ => healthy(op, data),
    });
    assert!(reader.unwrap().inventory().unwrap().is_empty());
}

#[test]
fn a_bad_crc_is_an_error_that_shows_the_frame() {
    let (reader, _peer) = reader_with(|op, data| match op {
        0x22 => {
            let mut frame = response(op, 0, &[0x00, 0x00, 0x01, 2]);
            let last = frame.len() - 1;
            frame[last] ^= 0xFF;
            Answer::Frame(frame)
        }
        _ => healthy(op, data),
    });
    let reason = failure(reader.unwrap().inventory());
    assert!(reason.starts_with("bad CRC in frame FF 04 22 00 00 00 00 01 02"), "{reason}");
    assert!(reason.contains("in answer to FF 05 22 00 00 01 00 32"), "{reason}");
}

#[test]
fn a_short_frame_and_no_answer_end_at_the_timeout() {
    let (reader, _peer) = reader_with(|op, data| match op {
        0x22 => Answer::Frame(response(op, 0, &[0x00, 0x00, 0x01, 2])[..4].to_vec()),
        _ => healthy(op, data),
    });
    let started = Instant::now();
    let reason = failure(reader.unwrap().inventory());
    assert!(reason.starts_with("a short frame: only FF 04 22 00 arrived"), "{reason}");
    assert!(started.elapsed() < Duration::from_secs(2), "{:?}", started.elapsed());

    let (reader, _peer) = reader_with(|op, data| match op {
        0x93 => Answer::Silence,
        _ => healthy(op, data),
    });
    let started = Instant::now();
    let reason = failure(reader);
    assert_eq!(reason, "no answer (in answer to FF 02 93 00 05 51 7D)");
    assert!(started.elapsed() < Duration::from_secs(2), "{:?}", started.elapsed());
}
