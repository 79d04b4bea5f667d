//! [`M5eReader`]: the paper's ThingMagic M5e (and other Mercury embedded modules) on a serial
//! port, behind [`RfidReader`]. Opening sets region, Gen2, read power and the antenna list; each
//! round is read-tag-multiple then get-tag-buffer with RSSI and antenna.
//!
//! Every wait ends at a timeout, and every bad frame is a [`HalError`] that shows its bytes.

use std::io::{ErrorKind, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use pps_schema::Epc;
use serialport::SerialPort;
use tracing::{debug, warn};

use super::frame::{
    NO_TAGS_FOUND, RESPONSE_OVERHEAD, Response, command, hex, opcode, parse_response,
};
use crate::hal::{AntennaId, HalError, RfidReader, TagRead};

const DEVICE: &str = "the M5e reader";
/// `SET_TAG_PROTOCOL`'s value for EPCglobal Gen2.
const PROTOCOL_GEN2: u16 = 0x0005;
/// Get-tag-buffer metadata: read count, RSSI and antenna.
const METADATA_READ_COUNT: u16 = 0x0001;
const METADATA_RSSI: u16 = 0x0002;
const METADATA_ANTENNA: u16 = 0x0004;

/// The regulatory regions of `SET_REGION`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Region {
    NorthAmerica,
    Europe,
    Korea,
    India,
    Japan,
    China,
    Australia,
    NewZealand,
}

impl Region {
    pub fn code(self) -> u8 {
        match self {
            Self::NorthAmerica => 0x01,
            Self::Europe => 0x02,
            Self::Korea => 0x03,
            Self::India => 0x04,
            Self::Japan => 0x05,
            Self::China => 0x06,
            Self::Australia => 0x0B,
            Self::NewZealand => 0x0C,
        }
    }

    /// `na`, `eu`, `kr`, `in`, `jp`, `cn`, `au`, `nz`.
    pub fn parse(name: &str) -> Option<Self> {
        Some(match name.to_ascii_lowercase().as_str() {
            "na" => Self::NorthAmerica,
            "eu" => Self::Europe,
            "kr" => Self::Korea,
            "in" => Self::India,
            "jp" => Self::Japan,
            "cn" => Self::China,
            "au" => Self::Australia,
            "nz" => Self::NewZealand,
            _ => return None,
        })
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct M5eSettings {
    /// The serial device, e.g. /dev/ttyUSB0.
    pub device: String,
    pub baud: u32,
    pub region: Region,
    /// Antenna ports to read, as numbered on the module (the M5e has 1 and 2); empty is port 1.
    pub antennas: Vec<u8>,
    /// Read power, dBm (the M5e goes from 5 to 30 dBm); `None` keeps the module's setting.
    pub read_power_dbm: Option<f64>,
    /// How long the module searches in one round.
    pub round: Duration,
    /// How long past what a command should take an answer may come.
    pub response_timeout: Duration,
}

impl M5eSettings {
    pub fn new(device: &str) -> Self {
        Self {
            device: device.to_owned(),
            baud: 115_200,
            region: Region::NorthAmerica,
            antennas: Vec::new(),
            read_power_dbm: None,
            round: Duration::from_millis(200),
            response_timeout: Duration::from_millis(500),
        }
    }
}

#[derive(Debug)]
pub struct M5eReader {
    settings: M5eSettings,
    port: Mutex<Box<dyn SerialPort>>,
    /// The module's version answer, as hex.
    pub version: String,
}

impl M5eReader {
    /// Opens the serial device and sets the module up.
    pub fn open(settings: M5eSettings) -> Result<Self, HalError> {
        let port = serialport::new(&settings.device, settings.baud)
            .timeout(settings.response_timeout)
            .open()
            .map_err(|e| HalError::Unavailable {
                device: DEVICE,
                reason: format!("cannot open {}: {e}", settings.device),
            })?;
        Self::on_port(settings, port)
    }

    /// Sets up a module on a port already open (a pseudo-terminal in tests).
    pub fn on_port(settings: M5eSettings, port: Box<dyn SerialPort>) -> Result<Self, HalError> {
        let reader = Self { settings, port: Mutex::new(port), version: String::new() };
        let version = reader.transact(opcode::GET_VERSION, &[], Duration::ZERO)?;
        let reader = Self { version: hex(&version.data), ..reader };
        debug!(version = %reader.version, "M5e version");
        let s = &reader.settings;
        reader.transact(opcode::SET_REGION, &[s.region.code()], Duration::ZERO)?;
        reader.transact(opcode::SET_TAG_PROTOCOL, &PROTOCOL_GEN2.to_be_bytes(), Duration::ZERO)?;
        if let Some(dbm) = s.read_power_dbm {
            if !(5.0..=30.0).contains(&dbm) {
                return Err(HalError::OutOfRange {
                    device: DEVICE,
                    reason: format!("read power {dbm} dBm is outside the M5e's 5 to 30 dBm"),
                });
            }
            let centi = (dbm * 100.0).round() as u16;
            reader.transact(opcode::SET_READ_TX_POWER, &centi.to_be_bytes(), Duration::ZERO)?;
        }
        // Option 2: the antenna search list, (transmit, receive) pairs; finger antennas are
        // monostatic, so each port transmits and receives.
        let ports = if s.antennas.is_empty() { vec![1] } else { s.antennas.clone() };
        let mut list = vec![0x02];
        for port in ports {
            list.extend_from_slice(&[port, port]);
        }
        reader.transact(opcode::SET_ANTENNA_PORT, &list, Duration::ZERO)?;
        Ok(reader)
    }

    /// Sends one command and reads its response; `busy` is how long the module works on it
    /// before answering.
    fn transact(&self, op: u8, data: &[u8], busy: Duration) -> Result<Response, HalError> {
        let mut port = self.port.lock().unwrap_or_else(|e| e.into_inner());
        let frame = command(op, data);
        // Whatever a previous, timed-out command left behind is not this one's answer.
        let _ = port.clear(serialport::ClearBuffer::Input);
        port.write_all(&frame).and_then(|()| port.flush()).map_err(|e| HalError::Unavailable {
            device: DEVICE,
            reason: format!("writing {} to {} failed: {e}", hex(&frame), self.settings.device),
        })?;
        let deadline = Instant::now() + busy + self.settings.response_timeout;
        let response = read_frame(&mut **port, deadline).map_err(|reason| HalError::Failed {
            device: DEVICE,
            reason: format!("{reason} (in answer to {})", hex(&frame)),
        })?;
        if response.opcode != op {
            return Err(HalError::Failed {
                device: DEVICE,
                reason: format!(
                    "{} answered opcode {:02X} to a command of opcode {op:02X}",
                    self.settings.device, response.opcode
                ),
            });
        }
        if response.status != 0
            && !(op == opcode::READ_TAG_MULTIPLE && response.status == NO_TAGS_FOUND)
        {
            return Err(HalError::Failed {
                device: DEVICE,
                reason: format!(
                    "the module answered {} with status {:04X}",
                    hex(&frame),
                    response.status
                ),
            });
        }
        Ok(response)
    }
}

/// One response frame, skipping noise before its 0xFF, by `deadline`.
fn read_frame(port: &mut dyn SerialPort, deadline: Instant) -> Result<Response, String> {
    let mut frame: Vec<u8> = Vec::with_capacity(64);
    let mut chunk = [0u8; 64];
    loop {
        let wanted = match frame.get(1) {
            None => 2,
            Some(&len) => usize::from(len) + RESPONSE_OVERHEAD,
        };
        if frame.len() >= wanted {
            return parse_response(&frame[..wanted]);
        }
        let now = Instant::now();
        if now >= deadline {
            return Err(if frame.is_empty() {
                "no answer".to_owned()
            } else {
                format!("a short frame: only {} arrived before the timeout", hex(&frame))
            });
        }
        let _ = port.set_timeout(deadline - now);
        let want = wanted - frame.len();
        match port.read(&mut chunk[..want.min(64)]) {
            Ok(0) => {}
            Ok(n) => {
                frame.extend_from_slice(&chunk[..n]);
                // Drop noise before the frame's start.
                if let Some(start) = frame.iter().position(|&b| b == 0xFF) {
                    if start > 0 {
                        warn!("skipped {} before a frame", hex(&frame[..start]));
                        frame.drain(..start);
                    }
                } else {
                    warn!("skipped {}, which is not a frame", hex(&frame));
                    frame.clear();
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted
                ) => {}
            Err(e) => return Err(format!("reading the serial port failed: {e}")),
        }
    }
}

/// The tag records of a get-tag-buffer answer: metadata flags, read options, tag count, then
/// per tag the metadata asked for, the EPC's bit length (PC and CRC words included), PC, EPC
/// and CRC.
pub fn parse_tag_buffer(data: &[u8]) -> Result<Vec<TagRead>, String> {
    let bad = |why: &str| format!("tag buffer {}: {why}", hex(data));
    if data.len() < 4 {
        return Err(bad("too short for its header"));
    }
    let flags = u16::from_be_bytes([data[0], data[1]]);
    let count = usize::from(data[3]);
    let mut at = 4;
    let mut take = |n: usize| -> Result<&[u8], String> {
        let slice = data.get(at..at + n).ok_or_else(|| bad("ends inside a tag record"))?;
        at += n;
        Ok(slice)
    };
    let mut reads = Vec::with_capacity(count);
    for _ in 0..count {
        let times = if flags & METADATA_READ_COUNT != 0 { take(1)?[0].max(1) } else { 1 };
        let rssi = if flags & METADATA_RSSI != 0 { Some(take(1)?[0] as i8) } else { None };
        // Newer firmware packs (transmit << 4 | receive); the receiving port is the antenna.
        let antenna = if flags & METADATA_ANTENNA != 0 {
            let byte = take(1)?[0];
            if byte > 0x0F { byte & 0x0F } else { byte }
        } else {
            1
        };
        let bits = u16::from_be_bytes(take(2)?.try_into().expect("two bytes"));
        let bytes = usize::from(bits).div_ceil(8);
        if bytes < 4 {
            return Err(bad("a tag record shorter than its PC and CRC"));
        }
        let record = take(bytes)?;
        let epc = &record[2..bytes - 2];
        let epc_hex: String = epc.iter().map(|b| format!("{b:02X}")).collect();
        let epc = Epc::parse(&epc_hex).map_err(|e| bad(&format!("EPC {epc_hex}: {e}")))?;
        let rssi = rssi.ok_or_else(|| bad("the module gave no RSSI"))?;
        for _ in 0..times {
            reads.push(TagRead {
                epc: epc.clone(),
                rssi_dbm: f64::from(rssi),
                antenna: AntennaId(antenna),
            });
        }
    }
    Ok(reads)
}

impl RfidReader for M5eReader {
    fn inventory(&self) -> Result<Vec<TagRead>, HalError> {
        let round_ms = self.settings.round.as_millis().min(u128::from(u16::MAX)) as u16;
        self.transact(opcode::CLEAR_TAG_BUFFER, &[], Duration::ZERO)?;
        // Option 0, search flag 1 (the configured antenna list), the search's duration.
        let mut request = vec![0x00, 0x00, 0x01];
        request.extend_from_slice(&round_ms.to_be_bytes());
        let found = self.transact(opcode::READ_TAG_MULTIPLE, &request, self.settings.round)?;
        if found.status == NO_TAGS_FOUND {
            return Ok(Vec::new());
        }
        // Old firmware answers with the count alone, newer with option, flags and count.
        let count = match found.data.as_slice() {
            [count] => usize::from(*count),
            [_, _, _, count, ..] => usize::from(*count),
            other => {
                return Err(HalError::Failed {
                    device: DEVICE,
                    reason: format!(
                        "read-tag-multiple answered {} instead of a tag count",
                        hex(other)
                    ),
                });
            }
        };
        let mut reads = Vec::new();
        let flags = METADATA_READ_COUNT | METADATA_RSSI | METADATA_ANTENNA;
        let mut records = 0;
        while records < count {
            let mut request = flags.to_be_bytes().to_vec();
            request.push(0x00);
            let buffer = self.transact(opcode::GET_TAG_BUFFER, &request, Duration::ZERO)?;
            let batch = buffer.data.get(3).copied().unwrap_or(0) as usize;
            if batch == 0 {
                break;
            }
            records += batch;
            reads.extend(
                parse_tag_buffer(&buffer.data)
                    .map_err(|reason| HalError::Failed { device: DEVICE, reason })?,
            );
        }
        Ok(reads)
    }
}
