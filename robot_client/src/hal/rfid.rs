//! The short-range UHF RFID readers in the fingers (paper §IV-A).

use pps_schema::Epc;

use super::HalError;

/// One of the finger antennas. EL-E has two per finger at 90° to each other: 0 and 1 on the
/// left finger, 2 and 3 on the right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct AntennaId(pub u8);

/// One reply of one tag to one antenna.
#[derive(Debug, Clone, PartialEq)]
pub struct TagRead {
    pub epc: Epc,
    /// Receive signal strength, dBm (larger is stronger, e.g. -45 close, -60 far).
    pub rssi_dbm: f64,
    pub antenna: AntennaId,
}

/// The finger RFID readers. Any tag in range may answer, not only the one in front of the
/// fingers: the paper saw reads up to 50 cm away.
pub trait RfidReader: Send + Sync {
    /// One inventory round over every antenna; every tag that answered, once per antenna.
    fn inventory(&self) -> Result<Vec<TagRead>, HalError>;
}
