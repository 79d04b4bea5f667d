//! [`LlrpReader`]: a [`RfidReader`] over LLRP. It connects on first use, runs one ROSpec round
//! per [`RfidReader::inventory`], reconnects when the connection broke between rounds, and says
//! goodbye (our ROSpec deleted, CLOSE_CONNECTION) when dropped.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use pps_schema::Epc;
use tracing::warn;

use super::params::report::TagReportData;
use super::session::{Round, Session, SessionError};
use super::settings::LlrpSettings;
use crate::hal::{AntennaId, HalError, RfidReader, TagRead};

const DEVICE: &str = "the LLRP reader";

#[derive(Debug)]
pub struct LlrpReader {
    settings: LlrpSettings,
    session: Mutex<Option<Session>>,
}

impl LlrpReader {
    /// A reader that connects on its first round.
    pub fn new(settings: LlrpSettings) -> Self {
        Self { settings, session: Mutex::new(None) }
    }

    /// A reader already connected and set up, so an unreachable one is known at once.
    pub fn connect(settings: LlrpSettings) -> Result<Self, HalError> {
        let session = open(&settings).map_err(into_hal)?;
        Ok(Self { settings, session: Mutex::new(Some(session)) })
    }

    pub fn settings(&self) -> &LlrpSettings {
        &self.settings
    }

    fn round(&self) -> Result<Round, HalError> {
        let mut slot = self.session.lock().unwrap_or_else(|e| e.into_inner());
        // A connection that broke since the last round gets one fresh try.
        let mut retried = slot.is_none();
        loop {
            let session = match slot.as_mut() {
                Some(session) => session,
                None => slot.insert(open(&self.settings).map_err(into_hal)?),
            };
            match session.round(&self.settings) {
                Ok(round) => {
                    if session.unanswered {
                        // The reader missed a request: begin the next round on a fresh session.
                        if let Some(session) = slot.take() {
                            session.close();
                        }
                    }
                    return Ok(round);
                }
                Err(SessionError::Broken(why)) if !retried => {
                    warn!("{why}; reconnecting");
                    *slot = None;
                    retried = true;
                }
                Err(error) => {
                    // Whatever state the reader is in now, the next round starts afresh.
                    if let Some(session) = slot.take() {
                        session.close();
                    }
                    return Err(into_hal(error));
                }
            }
        }
    }
}

/// How often to knock again while another client holds the reader.
const BUSY_RETRY: Duration = Duration::from_millis(100);

fn open(settings: &LlrpSettings) -> Result<Session, SessionError> {
    // A reader still closing the previous client's connection refuses the next one for a
    // moment; keep knocking until the connect timeout.
    let give_up = Instant::now() + settings.connect_timeout;
    let mut session = loop {
        match Session::connect(settings) {
            Err(SessionError::Busy(_)) if Instant::now() + BUSY_RETRY < give_up => {
                #[allow(clippy::disallowed_methods, reason = "a real reader needs a moment")]
                std::thread::sleep(BUSY_RETRY);
            }
            other => break other?,
        }
    };
    match session.set_up(settings) {
        Ok(()) => Ok(session),
        Err(error) => {
            session.close();
            Err(error)
        }
    }
}

fn into_hal(error: SessionError) -> HalError {
    match error {
        SessionError::Broken(reason)
        | SessionError::Busy(reason)
        | SessionError::Unreachable(reason) => HalError::Unavailable { device: DEVICE, reason },
        SessionError::Refused(reason) => HalError::Failed { device: DEVICE, reason },
    }
}

/// The read a hal user sees, or why a report cannot be one (an EPC that is not whole 16-bit
/// words, no antenna or no RSSI).
pub fn tag_read(report: &TagReportData) -> Result<TagRead, String> {
    let hex = report.epc.to_hex();
    if !report.epc.bits.is_multiple_of(16)
        || usize::from(report.epc.bits) != report.epc.bytes.len() * 8
    {
        return Err(format!("EPC {hex} is {} bits, not whole 16-bit words", report.epc.bits));
    }
    let epc = Epc::parse(&hex).map_err(|e| format!("EPC {hex}: {e}"))?;
    let antenna = report.antenna_id.ok_or_else(|| format!("the read of {hex} names no antenna"))?;
    let antenna = u8::try_from(antenna).map_err(|_| format!("antenna {antenna} is above 255"))?;
    let rssi = report.peak_rssi.ok_or_else(|| format!("the read of {hex} has no PeakRSSI"))?;
    Ok(TagRead { epc, rssi_dbm: f64::from(rssi), antenna: AntennaId(antenna) })
}

impl RfidReader for LlrpReader {
    fn inventory(&self) -> Result<Vec<TagRead>, HalError> {
        let round = self.round()?;
        let mut reads = Vec::with_capacity(round.reports.len());
        for report in &round.reports {
            match tag_read(report) {
                Ok(read) => reads.push(read),
                Err(why) => warn!("skipped a tag report: {why}"),
            }
        }
        let asked: Vec<u16> = self.settings.antennas.clone();
        let all_lost = !asked.is_empty() && asked.iter().all(|a| round.lost_antennas.contains(a));
        if reads.is_empty() && all_lost {
            return Err(HalError::Unavailable {
                device: DEVICE,
                reason: format!(
                    "the reader reported every antenna of the round disconnected ({})",
                    asked.iter().map(u16::to_string).collect::<Vec<_>>().join(", ")
                ),
            });
        }
        Ok(reads)
    }
}

impl Drop for LlrpReader {
    fn drop(&mut self) {
        let slot = self.session.get_mut().unwrap_or_else(|e| e.into_inner());
        if let Some(session) = slot.take() {
            session.close();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rfid::llrp::params::report::EpcData;

    #[test]
    fn reports_become_reads_or_say_why_not() {
        let mut report = TagReportData::of(EpcData::from_bytes(&[0xE2; 16]));
        report.antenna_id = Some(4);
        report.peak_rssi = Some(-48);
        let read = tag_read(&report).unwrap();
        assert_eq!(
            (read.epc.as_hex().len(), read.antenna, read.rssi_dbm),
            (32, AntennaId(4), -48.0)
        );
        report.peak_rssi = None;
        assert!(tag_read(&report).unwrap_err().contains("no PeakRSSI"));
        let odd = TagReportData {
            antenna_id: Some(1),
            peak_rssi: Some(-50),
            ..TagReportData::of(EpcData { bits: 100, bytes: vec![0; 13] })
        };
        assert!(tag_read(&odd).unwrap_err().contains("100 bits"));
    }
}
