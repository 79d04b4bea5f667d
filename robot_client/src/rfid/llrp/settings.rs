//! How an LLRP reader is reached and how its rounds run: what the robot's command line and
//! configuration set, and what the session sends the reader.

use std::time::Duration;

/// How a round ends on the reader (our own clock ends it too, at `round` plus a little).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoundStop {
    /// After the round's duration.
    Duration,
    /// After this many tag reads, or the round's duration if fewer come.
    Tags(u16),
}

/// Where the reader is and how it is to inventory.
#[derive(Debug, Clone, PartialEq)]
pub struct LlrpSettings {
    /// `HOST[:PORT]`; port 5084 unless given.
    pub address: String,
    /// The reader's antenna ports to inventory, as numbered on the reader (from 1); empty is all.
    pub antennas: Vec<u16>,
    /// How long one inventory round lasts.
    pub round: Duration,
    pub stop: RoundStop,
    /// Transmit power, dBm; the nearest entry of the reader's power table is used. `None`
    /// leaves the reader's own setting.
    pub read_power_dbm: Option<f64>,
    /// Ask the reader to return to its factory configuration when connecting.
    pub reset_to_factory_default: bool,
    pub connect_timeout: Duration,
    /// How long any one answer may take.
    pub response_timeout: Duration,
}

impl LlrpSettings {
    pub fn new(address: &str) -> Self {
        Self {
            address: address.to_owned(),
            antennas: Vec::new(),
            round: Duration::from_millis(200),
            stop: RoundStop::Duration,
            read_power_dbm: None,
            reset_to_factory_default: false,
            connect_timeout: Duration::from_secs(3),
            response_timeout: Duration::from_secs(2),
        }
    }
}
