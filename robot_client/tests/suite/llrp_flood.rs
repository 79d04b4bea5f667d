//! `pps-robot rfid` against LLRP readers that misbehave on purpose: one that floods tag reports
//! instead of answering, one that floods them during a round, one that never reads what it is
//! sent. Each is a socket peer in this process; the robot is the real binary.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::process::{Child, Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use pps_robot::rfid::llrp::connection::Connection;
use pps_robot::rfid::llrp::messages::Message;
use pps_robot::rfid::llrp::params::events::{
    ConnectionAttemptStatus, EventTimestamp, ReaderEventNotificationData,
};
use pps_robot::rfid::llrp::params::report::{EpcData, TagReportData};
use pps_robot::rfid::llrp::params::status::LlrpStatus;
use serde_json::Value;

/// Tags in each flooding report, as in the report that found the problem.
const TAGS_PER_REPORT: usize = 60_000;
/// The one tag held close to the antenna during a flooded round.
const HELD: [u8; 12] = [0x35, 0x5A, 0xB1, 0xC6, 0, 0, 0, 0x10, 0, 0, 0, 0x01];

#[derive(Clone, Copy, PartialEq)]
enum Misbehaviour {
    /// Streams tag reports from the start and answers nothing.
    FloodsInsteadOfAnswering,
    /// Answers everything, but a started round floods until it is stopped.
    FloodsEachRound,
    /// Sends keepalives without end and never reads a byte.
    NeverReads,
    /// Answers everything, and a round is one report as large as a message may be.
    SendsOneHugeReport,
}

/// What the peer saw of the robot.
#[derive(Default)]
struct Seen {
    requests: Mutex<Vec<String>>,
    /// The robot's peak resident memory, KiB, read from /proc as each request arrived.
    peak_kib: AtomicU64,
    robot_pid: AtomicU32,
}

impl Seen {
    fn requested(&self, name: &str) -> bool {
        self.requests.lock().unwrap().iter().any(|r| r == name)
    }

    fn note_memory(&self) {
        let pid = self.robot_pid.load(Ordering::SeqCst);
        let Ok(status) = std::fs::read_to_string(format!("/proc/{pid}/status")) else { return };
        let hwm = status
            .lines()
            .find_map(|l| l.strip_prefix("VmHWM:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok());
        if let (true, Some(kib)) = (pid != 0, hwm) {
            self.peak_kib.fetch_max(kib, Ordering::SeqCst);
        }
    }
}

struct FakeReader {
    address: String,
    seen: Arc<Seen>,
    thread: Option<JoinHandle<()>>,
}

fn flood_report(first_serial: u32, held_rssi: Option<i8>) -> Vec<u8> {
    let mut tags = Vec::with_capacity(TAGS_PER_REPORT + 1);
    if let Some(rssi) = held_rssi {
        tags.push(read(&HELD, rssi));
    }
    for serial in first_serial..first_serial + TAGS_PER_REPORT as u32 {
        let mut epc = [0xE2, 0x80, 0x11, 0x60, 0, 0, 0, 0, 0, 0, 0, 0];
        epc[8..].copy_from_slice(&serial.to_be_bytes());
        tags.push(read(&epc, -62));
    }
    Message::RoAccessReport { tags }.encode(0)
}

/// One report of 600,000 different tags, just under the 16 MiB a message may be, the held tag
/// strongest among them.
fn huge_report() -> Vec<u8> {
    let mut tags = vec![read(&HELD, -41)];
    for serial in 0..600_000u32 {
        let mut epc = [0xE2, 0x80, 0x11, 0x60, 0, 0, 0, 0, 0, 0, 0, 0];
        epc[8..].copy_from_slice(&serial.to_be_bytes());
        tags.push(read(&epc, -62));
    }
    Message::RoAccessReport { tags }.encode(0)
}

fn read(epc: &[u8], rssi: i8) -> TagReportData {
    TagReportData {
        antenna_id: Some(1),
        peak_rssi: Some(rssi),
        rospec_id: Some(0x5050),
        ..TagReportData::of(EpcData::from_bytes(epc))
    }
}

fn response_to(request: &Message) -> Option<Message> {
    let ok = LlrpStatus::success;
    Some(match request {
        Message::GetReaderCapabilities { .. } => {
            Message::GetReaderCapabilitiesResponse { status: ok(), general: None, regulatory: None }
        }
        Message::SetReaderConfig(_) => Message::SetReaderConfigResponse { status: ok() },
        Message::GetRoSpecs => Message::GetRoSpecsResponse { status: ok(), rospecs: vec![] },
        Message::AddRoSpec { .. } => Message::AddRoSpecResponse { status: ok() },
        Message::EnableRoSpec { .. } => Message::EnableRoSpecResponse { status: ok() },
        Message::DisableRoSpec { .. } => Message::DisableRoSpecResponse { status: ok() },
        Message::DeleteRoSpec { .. } => Message::DeleteRoSpecResponse { status: ok() },
        Message::StartRoSpec { .. } => Message::StartRoSpecResponse { status: ok() },
        Message::StopRoSpec { .. } => Message::StopRoSpecResponse { status: ok() },
        Message::CloseConnection => Message::CloseConnectionResponse { status: ok() },
        _ => return None,
    })
}

/// Reads the robot's messages until it hangs up, noting each and passing it on.
fn listen(mut stream: TcpStream, seen: Arc<Seen>, to_writer: mpsc::Sender<(u32, Message)>) {
    loop {
        let mut header = [0u8; 10];
        if stream.read_exact(&mut header).is_err() {
            return;
        }
        let length = u32::from_be_bytes(header[2..6].try_into().unwrap()) as usize;
        let mut bytes = header.to_vec();
        bytes.resize(length.max(10), 0);
        if stream.read_exact(&mut bytes[10..]).is_err() {
            return;
        }
        let (id, message) = Message::decode(&bytes).expect("the robot sends sound LLRP");
        seen.note_memory();
        seen.requests.lock().unwrap().push(message.name());
        if to_writer.send((id, message)).is_err() {
            return;
        }
    }
}

impl FakeReader {
    fn start(misbehaviour: Misbehaviour) -> Self {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap().to_string();
        let seen = Arc::new(Seen::default());
        let peer_seen = seen.clone();
        let thread = std::thread::spawn(move || {
            let (mut stream, _) = listener.accept().unwrap();
            let mut hello = ReaderEventNotificationData::at(EventTimestamp::Utc(1));
            hello.connection_attempt = Some(ConnectionAttemptStatus::Success);
            let hello = Message::ReaderEventNotification { data: hello }.encode(0);
            if stream.write_all(&hello).is_err() {
                return;
            }
            // Every write below fails once the robot is gone, which ends the peer.
            match misbehaviour {
                Misbehaviour::NeverReads => {
                    let mut id = 0u32;
                    while stream.write_all(&Message::Keepalive.encode(id)).is_ok() {
                        id = id.wrapping_add(1);
                    }
                }
                Misbehaviour::FloodsInsteadOfAnswering => {
                    let (to_writer, _requests) = mpsc::channel();
                    let incoming = stream.try_clone().unwrap();
                    std::thread::spawn(move || listen(incoming, peer_seen, to_writer));
                    let report = flood_report(0, None);
                    while stream.write_all(&report).is_ok() {}
                }
                Misbehaviour::FloodsEachRound | Misbehaviour::SendsOneHugeReport => {
                    let (to_writer, requests) = mpsc::channel();
                    let incoming = stream.try_clone().unwrap();
                    std::thread::spawn(move || listen(incoming, peer_seen, to_writer));
                    // The held tag is strongest in the first report, weaker after.
                    let huge = (misbehaviour == Misbehaviour::SendsOneHugeReport).then(huge_report);
                    let reports: Vec<Vec<u8>> = (0..4u32)
                        .map(|i| {
                            flood_report(
                                i * TAGS_PER_REPORT as u32,
                                Some(if i == 0 { -41 } else { -50 }),
                            )
                        })
                        .collect();
                    let mut flooding = None;
                    loop {
                        let next = match flooding {
                            None => requests.recv().map_err(|_| ()),
                            Some(_) => match requests.try_recv() {
                                Ok(request) => Ok(request),
                                Err(mpsc::TryRecvError::Empty) => Err(()),
                                Err(mpsc::TryRecvError::Disconnected) => return,
                            },
                        };
                        match next {
                            Ok((id, request)) => {
                                match request {
                                    Message::StartRoSpec { .. } if huge.is_none() => {
                                        flooding = Some(0)
                                    }
                                    Message::StopRoSpec { .. } => flooding = None,
                                    _ => {}
                                }
                                let Some(response) = response_to(&request) else { continue };
                                if stream.write_all(&response.encode(id)).is_err()
                                    || request == Message::CloseConnection
                                {
                                    return;
                                }
                                if let (Some(huge), Message::StartRoSpec { .. }) = (&huge, &request)
                                    && stream.write_all(huge).is_err()
                                {
                                    return;
                                }
                            }
                            Err(()) if flooding.is_none() => return,
                            Err(()) => {
                                let i = flooding.unwrap_or(0);
                                if stream.write_all(&reports[i % reports.len()]).is_err() {
                                    return;
                                }
                                flooding = Some(i + 1);
                            }
                        }
                    }
                }
            }
        });
        Self { address, seen, thread: Some(thread) }
    }

    /// Runs `pps-robot rfid --json` against this reader, and its output once it exits, or
    /// `None` when it is still running after `limit` (it is then killed).
    fn robot(&self, limit: Duration) -> (Option<Output>, Duration) {
        let started = Instant::now();
        let child = Command::new(env!("CARGO_BIN_EXE_pps-robot"))
            .args(["rfid", "--llrp", &self.address, "--rounds", "1", "--json"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the binary runs");
        self.seen.robot_pid.store(child.id(), Ordering::SeqCst);
        let output = wait_for_exit(child, limit);
        (output, started.elapsed())
    }

    /// What the peer saw, once the robot has gone.
    fn seen(mut self) -> Arc<Seen> {
        if let Some(thread) = self.thread.take() {
            thread.join().expect("the peer ends when the robot hangs up");
        }
        self.seen.clone()
    }
}

/// Waits for the child's exit on another thread, so a robot that hangs is killed, not waited on.
fn wait_for_exit(child: Child, limit: Duration) -> Option<Output> {
    let pid = child.id();
    let (done, exited) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = done.send(child.wait_with_output());
    });
    match exited.recv_timeout(limit) {
        Ok(output) => Some(output.expect("the robot's output")),
        Err(_) => {
            // Killed by its pid: the waiting thread still owns the Child.
            let _ = Command::new("kill").args(["-9", &pid.to_string()]).status();
            let _ = exited.recv();
            None
        }
    }
}

#[test]
fn a_reader_that_floods_instead_of_answering_is_told_to_stop_and_memory_stays_bounded() {
    let reader = FakeReader::start(Misbehaviour::FloodsInsteadOfAnswering);
    let (output, took) = reader.robot(Duration::from_secs(30));
    let output = output.expect("the robot gives up within 30 s");
    let seen = reader.seen();
    let peak_mib = seen.peak_kib.load(Ordering::SeqCst) / 1024;
    let stderr = String::from_utf8_lossy(&output.stderr);
    eprintln!("flood during set-up: exited after {took:?}, peak RSS {peak_mib} MiB\n{stderr}");
    assert!(!output.status.success(), "no set-up, no reads: {stderr}");
    assert!(output.stdout.is_empty(), "--json prints nothing when there is no document");
    assert!(seen.requested("DISABLE_ROSPEC"), "the reader is told to stop reading");
    assert!(
        stderr.contains("did not answer GET_READER_CAPABILITIES within 2.0 s")
            && stderr.contains("tag reads instead")
            && stderr.contains("told it to stop"),
        "{stderr}"
    );
    assert!(took < Duration::from_secs(8), "{took:?}");
    assert!(peak_mib < 150, "peak RSS {peak_mib} MiB while flooded");
}

#[test]
fn a_round_flooded_with_tags_keeps_the_strongest_read_and_stops_the_reader() {
    let reader = FakeReader::start(Misbehaviour::FloodsEachRound);
    let (output, took) = reader.robot(Duration::from_secs(30));
    let output = output.expect("the round ends within 30 s");
    let seen = reader.seen();
    let peak_mib = seen.peak_kib.load(Ordering::SeqCst) / 1024;
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let doc: Value = serde_json::from_slice(&output.stdout).expect("one JSON document");
    let reads = doc["reads"].as_array().unwrap().len();
    eprintln!(
        "flooded round: {reads} reads kept, took {took:?}, peak RSS {peak_mib} MiB\n{stderr}"
    );
    assert!(reads <= 4096, "{reads} reads kept of one round");
    assert_eq!(doc["chosen"], "355AB1C60000001000000001");
    assert_eq!(doc["tags"][0]["rssi_dbm"], -41.0, "the held tag's strongest read is kept");
    assert!(seen.requested("STOP_ROSPEC"));
    assert!(
        stderr.contains("different tags in one round") && stderr.contains("told it to stop"),
        "{stderr}"
    );
    assert!(peak_mib < 150, "peak RSS {peak_mib} MiB while flooded");
}

#[test]
fn a_report_as_large_as_a_message_may_be_is_never_held_decoded_whole() {
    let reader = FakeReader::start(Misbehaviour::SendsOneHugeReport);
    let (output, took) = reader.robot(Duration::from_secs(30));
    let output = output.expect("the round ends within 30 s");
    let seen = reader.seen();
    let peak_mib = seen.peak_kib.load(Ordering::SeqCst) / 1024;
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let doc: Value = serde_json::from_slice(&output.stdout).expect("one JSON document");
    eprintln!("one 16 MB report: took {took:?}, peak RSS {peak_mib} MiB");
    assert_eq!(doc["reads"].as_array().unwrap().len(), 4096);
    assert_eq!(doc["chosen"], "355AB1C60000001000000001");
    assert!(peak_mib < 64, "peak RSS {peak_mib} MiB for a 16 MB report");
}

#[test]
fn a_reader_that_never_reads_gives_up_like_an_unanswered_request() {
    let reader = FakeReader::start(Misbehaviour::NeverReads);
    let (output, took) = reader.robot(Duration::from_secs(30));
    let output = output.expect("the robot gives up within 30 s");
    let stderr = String::from_utf8_lossy(&output.stderr);
    eprintln!("reader that never reads: exited after {took:?}\n{stderr}");
    // Whether our acknowledgements fill the socket buffers before the first request's answer
    // is overdue depends on the machine's speed; either clock is 2 s, and the words for the
    // stalled write are the next test's.
    assert!(!output.status.success());
    assert!(output.stdout.is_empty());
    assert!(stderr.starts_with("error: the LLRP reader"), "{stderr}");
    assert!(stderr.contains(&reader.address), "{stderr}");
    assert!(took < Duration::from_secs(6), "a 2 s timeout, then goodbye: {took:?}");
    reader.seen();
}

#[test]
fn a_message_the_reader_does_not_take_gives_up_after_the_write_timeout() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let (done, outcome) = mpsc::channel();
    std::thread::spawn(move || {
        let timeout = Duration::from_millis(300);
        let mut connection = Connection::open(&address, timeout, timeout).unwrap();
        // Until the socket buffers are full every message goes out; then one waits, and fails.
        let failure = (0..10_000_000u32)
            .find_map(|id| connection.send_as(&Message::KeepaliveAck, id).err())
            .expect("the buffers fill long before ten million messages");
        let waited = Instant::now();
        let again = connection.send_as(&Message::KeepaliveAck, 0).expect_err("still stalled");
        let _ = done.send((failure.to_string(), again.to_string(), waited.elapsed()));
    });
    let (_peer, _) = listener.accept().unwrap();
    let (failure, again, waited) =
        outcome.recv_timeout(Duration::from_secs(20)).expect("the write gives up; it never did");
    assert!(
        failure.ends_with("stopped reading: KEEPALIVE_ACK did not go out within 0.3 s"),
        "{failure}"
    );
    assert_eq!(again, failure, "a message cut short breaks the stream: nothing more is sent");
    assert!(waited < Duration::from_millis(100), "{waited:?}");
}
