//! The registry's side of the node: an inventory round on `/pps/rfid` answered with the
//! robot's effective entry for the tag the round chose (§5: strongest RSSI, ambiguous within
//! the margin), and a trial on `/pps/trial` recorded through the durable outbox.
//!
//! Entries come through the registry client's cache, so the node keeps answering while the
//! registry is away; `error` is filled only when no answer can be given.

use pps_robot::hal::{AntennaId, TagRead as HalTagRead};
use pps_robot::navigation::{RfidIdentity, identify_tag};
use pps_robot::registry::{FlushReport, RegistryClient, RegistryError};
use pps_schema::{Epc, Trial as TrialDocument};

use crate::msg::builtin::Time;
use crate::msg::pps::{TagEntry, TagReads, Trial};

/// The reads of a round that name a valid EPC, and a sentence for each that does not.
pub fn hal_reads(round: &TagReads) -> (Vec<HalTagRead>, Vec<String>) {
    let mut reads = Vec::with_capacity(round.reads.len());
    let mut refused = Vec::new();
    for read in &round.reads {
        match Epc::parse(&read.epc) {
            Ok(epc) if read.rssi_dbm.is_finite() => reads.push(HalTagRead {
                epc,
                rssi_dbm: read.rssi_dbm,
                antenna: AntennaId(read.antenna),
            }),
            Ok(_) => refused.push(format!("the read of {} has no finite RSSI", read.epc)),
            Err(e) => refused.push(format!("`{}` is not an EPC: {e}", read.epc)),
        }
    }
    (reads, refused)
}

/// The answer to one inventory round.
pub async fn entry_for_round(
    registry: &RegistryClient,
    round: &TagReads,
    margin_db: f64,
) -> TagEntry {
    let (reads, _) = hal_reads(round);
    let stamp = Time::now();
    let Some(identity) = identify_tag(&reads, margin_db) else {
        return TagEntry {
            stamp,
            error: "no tag answered in this inventory round".into(),
            ..TagEntry::default()
        };
    };
    let ambiguous = matches!(identity, RfidIdentity::Ambiguous { .. });
    let epc = identity.strongest().epc.clone();
    let answer = TagEntry { stamp, epc: epc.as_hex().to_owned(), ambiguous, ..TagEntry::default() };
    match registry.effective_entry(&epc).await {
        Ok(fetched) => match serde_json::to_string(&fetched.document) {
            Ok(entry_json) => TagEntry {
                revision: format!("r{}", fetched.entry.revision),
                entry_json,
                unavailable_actions: fetched
                    .entry
                    .unavailable_actions
                    .iter()
                    .map(|u| u.action.clone())
                    .collect(),
                ..answer
            },
            Err(e) => {
                TagEntry { error: format!("the entry could not be written as JSON: {e}"), ..answer }
            }
        },
        Err(error) => TagEntry { error: entry_error(&epc, &error), ..answer },
    }
}

/// Why no entry could be given, as a sentence.
fn entry_error(epc: &Epc, error: &RegistryError) -> String {
    match error.status() {
        Some(404) => format!("tag {epc} is not registered (the registry noted it in its inbox)"),
        _ => format!("no entry for tag {epc}: {error}"),
    }
}

/// Why a trial message could not be recorded.
#[derive(Debug, thiserror::Error)]
pub enum TrialError {
    #[error("the trial is not a trial document: {0}")]
    Document(#[from] serde_json::Error),
    #[error("the trial {id} is not for this robot ({robot}) but for {claimed}")]
    OtherRobot { id: uuid::Uuid, robot: String, claimed: String },
    #[error("the trial could not be kept in the outbox: {0}")]
    Outbox(#[from] RegistryError),
}

/// The trial document a `/pps/trial` message carries, if it is one of this robot's.
pub fn trial_document(
    registry: &RegistryClient,
    message: &Trial,
) -> Result<TrialDocument, TrialError> {
    let trial: TrialDocument = serde_json::from_str(&message.trial_json)?;
    if &trial.robot != registry.robot() {
        return Err(TrialError::OtherRobot {
            id: trial.id,
            robot: registry.robot().to_string(),
            claimed: trial.robot.to_string(),
        });
    }
    Ok(trial)
}

/// Records a trial and its picture (PNG), if any: durably into the outbox, then uploads what is
/// waiting. The trial's own id makes the upload idempotent, so a retry after a lost answer
/// stores it once, picture included.
pub async fn record_trial(
    registry: &RegistryClient,
    trial: &TrialDocument,
    picture: Option<&[u8]>,
) -> Result<(uuid::Uuid, FlushReport), TrialError> {
    let report = registry.record_trial_with_picture(trial, picture).await?;
    Ok((trial.id, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msg::pps::TagRead;

    #[test]
    fn reads_with_bad_epcs_are_set_aside_in_words() {
        let round = TagReads {
            reads: vec![
                TagRead { epc: "E20034120000000000001001".into(), rssi_dbm: -48.0, antenna: 1 },
                TagRead { epc: "not-an-epc".into(), rssi_dbm: -50.0, antenna: 2 },
                TagRead { epc: "E200".into(), rssi_dbm: f64::NAN, antenna: 0 },
            ],
            ..TagReads::default()
        };
        let (reads, refused) = hal_reads(&round);
        assert_eq!(reads.len(), 1);
        assert_eq!(reads[0].antenna, AntennaId(1));
        assert_eq!(refused.len(), 2);
        assert!(refused[0].contains("not-an-epc"), "{refused:?}");
    }
}
