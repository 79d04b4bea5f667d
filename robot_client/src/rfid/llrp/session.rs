//! One controlling session with an LLRP reader: the set-up after connecting (capabilities,
//! configuration, stale ROSpecs deleted, ours added and enabled), inventory rounds, and the
//! goodbye. Everything the reader sends unasked — keepalives, events, reports — is handled
//! while waiting for whatever was asked.
//!
//! Longer than most files because the set-up is one conversation the standard orders (LLRP
//! 1.0.1 §17.1); read top to bottom it is that order.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use tracing::{debug, warn};

use super::connection::{Broken, Connection, Received};
use super::messages::{ALL_CAPABILITIES, Message, SetReaderConfig};
use super::params::capabilities::{GeneralDeviceCapabilities, RegulatoryCapabilities};
use super::params::config::{KeepaliveSpec, ReaderEventNotificationSpec, event_type};
use super::params::events::{
    ConnectionAttemptStatus, ReaderEventNotificationData, RoSpecEventKind,
};
use super::params::report::{TagReportData, for_each_tag_report};
use super::params::rospec::{
    AiSpec, AiSpecStopTrigger, AntennaConfiguration, EPC_GLOBAL_CLASS1_GEN2,
    InventoryParameterSpec, RfTransmitter, RoBoundarySpec, RoReportSpec, RoReportTrigger, RoSpec,
    RoSpecStartTrigger, RoSpecState, RoSpecStopTrigger, TagReportContentSelector,
};
use super::round_reads::{MAX_KEPT, RoundReads};
use super::settings::{LlrpSettings, RoundStop};
use super::wire::{FieldReader, MESSAGE_HEADER_LEN};

/// Our ROSpec's id ("PP" for PPS-tags); any stale one is deleted at connection.
pub const ROSPEC_ID: u32 = 0x5050;
/// The keepalive period asked of the reader.
const KEEPALIVE_PERIOD_MS: u32 = 10_000;
/// How long past its stop trigger a reader may take to end the ROSpec before we stop it.
const STOP_GRACE: Duration = Duration::from_millis(50);

/// Why a session step failed.
#[derive(Debug)]
pub enum SessionError {
    /// The connection broke; a new one may work.
    Broken(String),
    /// The reader said no, or did not answer in time; the words are ready for a person.
    Refused(String),
    /// Another client holds the reader (it takes one at a time).
    Busy(String),
    /// No TCP connection could be made.
    Unreachable(String),
}

/// One round's outcome.
#[derive(Debug, Default)]
pub struct Round {
    pub reports: Vec<TagReportData>,
    /// Antennas the reader said were disconnected (and not reconnected since).
    pub lost_antennas: BTreeSet<u16>,
}

#[derive(Debug)]
pub struct Session {
    connection: Connection,
    pub general: Option<GeneralDeviceCapabilities>,
    pub regulatory: Option<RegulatoryCapabilities>,
    response_timeout: Duration,
    /// The round's reads, gathered while waiting for anything; a round takes them.
    reads: RoundReads,
    /// Whether a round of ours is running, so its reports are ours to keep.
    in_round: bool,
    /// Tag reads that arrived while no round of ours ran: counted, never kept.
    stray_reads: u64,
    /// The reader was told to stop every ROSpec (DISABLE_ROSPEC 0), ours included.
    told_to_stop: bool,
    lost_antennas: BTreeSet<u16>,
    rospec_ended: bool,
    exception: Option<String>,
    /// A request went unanswered: the reader's state is unknown, so the session should end.
    pub unanswered: bool,
}

impl From<Broken> for SessionError {
    fn from(broken: Broken) -> Self {
        Self::Broken(broken.to_string())
    }
}

impl Session {
    /// Connects and reads the reader's connection event: it accepts us or says why not.
    pub fn connect(settings: &LlrpSettings) -> Result<Self, SessionError> {
        let connection = Connection::open(
            &settings.address,
            settings.connect_timeout,
            settings.response_timeout,
        )
        .map_err(SessionError::Unreachable)?;
        let mut session = Self {
            connection,
            general: None,
            regulatory: None,
            response_timeout: settings.response_timeout,
            reads: RoundReads::default(),
            in_round: false,
            stray_reads: 0,
            told_to_stop: false,
            lost_antennas: BTreeSet::new(),
            rospec_ended: false,
            exception: None,
            unanswered: false,
        };
        let deadline = Instant::now() + settings.response_timeout;
        loop {
            match session.connection.receive(deadline)? {
                None => {
                    return Err(SessionError::Refused(format!(
                        "{} accepted the TCP connection but sent no LLRP connection event within \
                         {:.1} s; is it an LLRP reader, and is LLRP enabled on it?",
                        session.connection.peer,
                        settings.response_timeout.as_secs_f64()
                    )));
                }
                Some(Received::Message {
                    message: Message::ReaderEventNotification { data },
                    ..
                }) if data.connection_attempt.is_some() => {
                    let status = data.connection_attempt.expect("checked above");
                    return match status.refusal() {
                        None => Ok(session),
                        Some(why) => {
                            session.connection.shutdown();
                            let sentence = format!(
                                "{} refused the connection: {why}",
                                session.connection.peer
                            );
                            Err(match status {
                                ConnectionAttemptStatus::ClientInitiatedConnectionExists => {
                                    SessionError::Busy(sentence)
                                }
                                _ => SessionError::Refused(sentence),
                            })
                        }
                    };
                }
                Some(other) => session.handle_unasked(other)?,
            }
        }
    }

    /// Reads capabilities, configures events and keepalives, deletes stale ROSpecs, and adds and
    /// enables the inventory ROSpec.
    pub fn set_up(&mut self, settings: &LlrpSettings) -> Result<(), SessionError> {
        if let Message::GetReaderCapabilitiesResponse { general, regulatory, .. } =
            self.ask(Message::GetReaderCapabilities { requested_data: ALL_CAPABILITIES })?
        {
            self.general = general;
            self.regulatory = regulatory;
        }
        if let Some(general) = &self.general {
            debug!(
                reader = %self.connection.peer,
                antennas = general.max_antennas,
                model = general.model,
                firmware = %general.firmware,
                "LLRP reader capabilities"
            );
            if let Some(&bad) =
                settings.antennas.iter().find(|&&a| a == 0 || a > general.max_antennas)
            {
                return Err(SessionError::Refused(format!(
                    "{} has antennas 1 to {}; there is no antenna {bad}",
                    self.connection.peer, general.max_antennas
                )));
            }
        }
        self.ask(Message::SetReaderConfig(SetReaderConfig {
            reset_to_factory_default: settings.reset_to_factory_default,
            event_notifications: Some(ReaderEventNotificationSpec {
                states: vec![
                    (event_type::ROSPEC_EVENT, true),
                    (event_type::READER_EXCEPTION_EVENT, true),
                    (event_type::ANTENNA_EVENT, true),
                ],
            }),
            keepalive: Some(KeepaliveSpec { period_ms: Some(KEEPALIVE_PERIOD_MS) }),
        }))?;
        if let Message::GetRoSpecsResponse { rospecs, .. } = self.ask(Message::GetRoSpecs)? {
            for stale in rospecs {
                debug!(rospec = stale.rospec_id, "deleting a stale ROSpec");
                self.ask(Message::DeleteRoSpec { rospec_id: stale.rospec_id })?;
            }
        }
        let rospec = self.inventory_rospec(settings)?;
        self.ask(Message::AddRoSpec { rospec })?;
        self.ask(Message::EnableRoSpec { rospec_id: ROSPEC_ID })?;
        Ok(())
    }

    fn inventory_rospec(&self, settings: &LlrpSettings) -> Result<RoSpec, SessionError> {
        let round_ms = settings.round.as_millis().min(u128::from(u32::MAX)) as u32;
        let antenna_ids =
            if settings.antennas.is_empty() { vec![0] } else { settings.antennas.clone() };
        let transmitter = match settings.read_power_dbm {
            None => None,
            Some(dbm) => {
                let regulatory = self.regulatory.as_ref();
                let Some(level) = regulatory.and_then(|r| r.nearest_power(dbm)) else {
                    return Err(SessionError::Refused(format!(
                        "{} lists no transmit power table, so a read power cannot be set",
                        self.connection.peer
                    )));
                };
                let hop_table_id =
                    regulatory.and_then(|r| r.hop_table_ids.first()).copied().unwrap_or(0);
                Some(RfTransmitter {
                    hop_table_id: u16::from(hop_table_id),
                    channel_index: 1,
                    transmit_power: level.index,
                })
            }
        };
        let antenna_configurations = match transmitter {
            None => Vec::new(),
            Some(t) => antenna_ids
                .iter()
                .map(|&antenna_id| AntennaConfiguration { antenna_id, transmitter: Some(t) })
                .collect(),
        };
        let stop = match settings.stop {
            RoundStop::Duration => AiSpecStopTrigger::DurationMs(round_ms),
            RoundStop::Tags(tags) => {
                AiSpecStopTrigger::TagsOrTimeout { tags, timeout_ms: round_ms }
            }
        };
        Ok(RoSpec {
            rospec_id: ROSPEC_ID,
            priority: 0,
            current_state: RoSpecState::Disabled,
            boundary: RoBoundarySpec {
                start: RoSpecStartTrigger::Null,
                stop: RoSpecStopTrigger::DurationMs(round_ms),
            },
            ai_specs: vec![AiSpec {
                antenna_ids,
                stop,
                inventory: vec![InventoryParameterSpec {
                    spec_id: 1,
                    protocol_id: EPC_GLOBAL_CLASS1_GEN2,
                    antenna_configurations,
                }],
            }],
            // Every read as it happens, so a round cut short still has what was read.
            report: Some(RoReportSpec {
                trigger: RoReportTrigger::UponNOrEndOfRoSpec,
                n: 1,
                content: TagReportContentSelector {
                    antenna_id: true,
                    peak_rssi: true,
                    first_seen_timestamp: true,
                    rospec_id: true,
                    ..TagReportContentSelector::default()
                },
            }),
        })
    }

    /// One inventory round: starts our ROSpec and gathers reports until the reader ends it or
    /// our own clock does.
    pub fn round(&mut self, settings: &LlrpSettings) -> Result<Round, SessionError> {
        if std::mem::take(&mut self.told_to_stop) {
            // Stopping a flood disabled our ROSpec too.
            self.ask(Message::EnableRoSpec { rospec_id: ROSPEC_ID })?;
        }
        self.reads.take();
        self.in_round = true;
        let result = self.gather_round(settings);
        self.in_round = false;
        result?;
        if let Some(exception) = self.exception.take() {
            return Err(SessionError::Refused(format!(
                "{} reported a failure during the round: \"{exception}\"",
                self.connection.peer
            )));
        }
        Ok(Round { reports: self.reads.take(), lost_antennas: self.lost_antennas.clone() })
    }

    fn gather_round(&mut self, settings: &LlrpSettings) -> Result<(), SessionError> {
        self.rospec_ended = false;
        self.exception = None;
        let started = Instant::now();
        self.ask(Message::StartRoSpec { rospec_id: ROSPEC_ID })?;
        let own_stop = started + settings.round + STOP_GRACE;
        let enough = match settings.stop {
            RoundStop::Tags(n) => u64::from(n),
            RoundStop::Duration => u64::MAX,
        };
        while !self.rospec_ended
            && self.reads.seen() < enough
            && self.exception.is_none()
            && !self.reads.overflowed()
        {
            match self.connection.receive(own_stop)? {
                None => break,
                Some(received) => self.handle_unasked(received)?,
            }
        }
        let flooded = self.reads.overflowed();
        let stopping = !self.rospec_ended;
        if stopping {
            // Not every reader ends a ROSpec on its trigger; a refusal here means it just did,
            // and no answer at all still leaves the reads we have (the session then ends).
            match self.ask(Message::StopRoSpec { rospec_id: ROSPEC_ID }) {
                Ok(_) => {}
                Err(SessionError::Refused(why)) => warn!("{why}; keeping the round's reads"),
                Err(broken) => return Err(broken),
            }
        }
        if flooded {
            warn!(
                "{} reported more different tags in one round than the {MAX_KEPT} a round keeps \
                 ({} reads), {}; the strongest read of each tag that fit is kept",
                self.connection.peer,
                self.reads.seen(),
                if stopping { "so we told it to stop the round" } else { "and it ended the round" }
            );
        }
        Ok(())
    }

    /// Deletes our ROSpec and closes the connection, each step bounded by a short timeout.
    pub fn close(mut self) {
        self.response_timeout = self.response_timeout.min(Duration::from_secs(1));
        self.connection.set_write_timeout(self.response_timeout);
        let _ = self.ask(Message::DeleteRoSpec { rospec_id: ROSPEC_ID });
        if let Err(SessionError::Refused(why)) = self.ask(Message::CloseConnection) {
            debug!("CLOSE_CONNECTION: {why}");
        }
        self.connection.shutdown();
    }

    /// Sends `request` and waits for its response, handling everything else that arrives.
    fn ask(&mut self, request: Message) -> Result<Message, SessionError> {
        let name = request.name();
        let id = self.connection.send(&request)?;
        let deadline = Instant::now() + self.response_timeout;
        loop {
            let Some(received) = self.connection.receive(deadline)? else {
                self.unanswered = true;
                let mut sentence = format!(
                    "{} did not answer {name} within {:.1} s",
                    self.connection.peer,
                    self.response_timeout.as_secs_f64()
                );
                if self.stray_reads > 0 && !self.in_round {
                    sentence.push_str(&format!("; it sent {} tag reads instead", self.stray_reads));
                    if self.told_to_stop {
                        sentence.push_str(", so we told it to stop reading");
                    }
                }
                return Err(SessionError::Refused(sentence));
            };
            match received {
                Received::Message { id: got, message }
                    if got == id && message.status().is_some() =>
                {
                    let status = message.status().expect("checked above");
                    if status.is_success() {
                        return Ok(message);
                    }
                    return Err(SessionError::Refused(format!(
                        "{} refused {name}: {status}",
                        self.connection.peer
                    )));
                }
                other => self.handle_unasked(other)?,
            }
        }
    }

    /// Whatever the reader sends that is not the answer being waited for.
    fn handle_unasked(&mut self, received: Received) -> Result<(), SessionError> {
        let (id, message) = match received {
            Received::Message { id, message } => (id, message),
            Received::Reports { bytes } => return self.note_reports(&bytes),
            Received::Undecodable { kind, error } => {
                warn!(reader = %self.connection.peer, "skipped a {kind} that did not decode: {error}");
                return Ok(());
            }
        };
        match message {
            Message::Keepalive => self.connection.send_as(&Message::KeepaliveAck, id)?,
            Message::ReaderEventNotification { data } => self.note_event(&data)?,
            Message::ErrorMessage { status } => {
                // An error about a request we are not waiting for: the reader's words, logged.
                warn!(reader = %self.connection.peer, "the reader sent ERROR_MESSAGE: {status}");
            }
            other => debug!(reader = %self.connection.peer, "ignored {}", other.name()),
        }
        Ok(())
    }

    /// An RO_ACCESS_REPORT's reads: the round's while one runs, else stray.
    fn note_reports(&mut self, bytes: &[u8]) -> Result<(), SessionError> {
        let mut body = FieldReader::new(bytes.get(MESSAGE_HEADER_LEN..).unwrap_or_default());
        let (in_round, reads) = (self.in_round, &mut self.reads);
        let mut stray = 0;
        let decoded =
            for_each_tag_report(
                &mut body,
                |tag| {
                    if in_round { reads.add(tag) } else { stray += 1 }
                },
            );
        if let Err(error) = decoded {
            warn!(reader = %self.connection.peer, "skipped the rest of an RO_ACCESS_REPORT that did not decode: {error}");
        }
        if stray > 0 {
            self.note_stray_reads(stray)?;
        }
        Ok(())
    }

    /// Reads while no round of ours runs belong to no one: a stale ROSpec, or a reader gone
    /// wrong. They are counted, and past a round's worth the reader is told to stop them all.
    fn note_stray_reads(&mut self, n: usize) -> Result<(), SessionError> {
        self.stray_reads += n as u64;
        if self.stray_reads > MAX_KEPT as u64 && !self.told_to_stop {
            warn!(
                "{} sent {} tag reads while no round of ours was running; telling it to stop \
                 reading (DISABLE_ROSPEC for all its ROSpecs)",
                self.connection.peer, self.stray_reads
            );
            self.told_to_stop = true;
            self.connection.send(&Message::DisableRoSpec { rospec_id: 0 })?;
        }
        Ok(())
    }

    fn note_event(&mut self, data: &ReaderEventNotificationData) -> Result<(), SessionError> {
        if let Some(antenna) = data.antenna {
            if antenna.connected {
                self.lost_antennas.remove(&antenna.antenna_id);
            } else {
                warn!(reader = %self.connection.peer, "antenna {} disconnected", antenna.antenna_id);
                self.lost_antennas.insert(antenna.antenna_id);
            }
        }
        if let Some(rospec) = data.rospec
            && rospec.rospec_id == ROSPEC_ID
            && matches!(rospec.kind, RoSpecEventKind::End | RoSpecEventKind::Preempted)
        {
            self.rospec_ended = true;
        }
        if let Some(exception) = &data.reader_exception {
            self.exception = Some(exception.clone());
        }
        if data.connection_close {
            return Err(SessionError::Broken(format!(
                "{} announced it is closing the connection",
                self.connection.peer
            )));
        }
        Ok(())
    }
}
