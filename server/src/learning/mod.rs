//! Learning from trials (the paper's "resource for self-guided learning"): parameter values
//! observed by a robot class, and whether an action has proven reliable for it.
//!
//! Runs inside the transaction that records or changes trials, so what was learned commits
//! with the evidence it rests on.

pub mod colour;
pub mod size;

use std::collections::BTreeSet;

use pps_schema::pointer::escape;
use pps_schema::{BehaviorKind, Epc};
use serde_json::{Value, json};
use sqlx::AnyConnection;

use crate::store::events::{self, EventKind};
use crate::store::trial_counts::{self, GroupKey};
use crate::store::{learning, tags};
use crate::trials::counted_purposes::CountedPurposes;

/// A parameter a behaviour's trials measure: its learned value is the median of the
/// measurement over the class's successful trials.
#[derive(Debug)]
struct LearningRule {
    behavior: BehaviorKind,
    measurement: &'static str,
    parameter: &'static str,
}

/// The paper's pull back records the drawer's observed displacement "for future use".
const RULES: [LearningRule; 1] = [LearningRule {
    behavior: BehaviorKind::PullBack,
    measurement: "displacement",
    parameter: "pull_distance",
}];

/// Trials a learned value is computed from (the most recent ones).
pub(crate) const LEARNING_WINDOW: i64 = 100;

/// The lab's rule: reliable after at least 20 attempts with at least 90 % success, judged over
/// the most recent attempts of real use so that a tag wearing out stops being reliable and an
/// experiment's deliberate failures do not count.
pub const RELIABLE_MIN_ATTEMPTS: i64 = 20;
pub const RELIABLE_MIN_SUCCESS: f64 = 0.9;
pub const RELIABILITY_WINDOW: i64 = 50;

pub fn is_reliable(attempts: i64, successes: i64) -> bool {
    attempts >= RELIABLE_MIN_ATTEMPTS && successes as f64 >= RELIABLE_MIN_SUCCESS * attempts as f64
}

pub fn median(mut values: Vec<f64>) -> Option<f64> {
    values.retain(|v| v.is_finite());
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let middle = values.len() / 2;
    Some(if values.len() % 2 == 1 {
        values[middle]
    } else {
        (values[middle - 1] + values[middle]) / 2.0
    })
}

/// Trials of one tag, action and robot class (`None` when the robot has none).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct TrialGroup {
    pub epc: Epc,
    pub action: String,
    pub behavior: String,
    pub robot_class: Option<String>,
    /// Whether what a learning rule measures may have changed: a new trial carrying one of the
    /// rules' measurements, or a changed verdict. Other trials only move reliability.
    pub relearn: bool,
}

/// A class as the change feed names it: `""` for robots without one, as it always has.
fn class_in_feed(robot_class: Option<&str>) -> &str {
    robot_class.unwrap_or("")
}

/// Whether a trial's measurements hold anything a learning rule learns from.
pub fn teaches(measurements: Option<&Value>) -> bool {
    measurements.is_some_and(|m| RULES.iter().any(|rule| m.get(rule.measurement).is_some()))
}

/// Recomputes what the groups' trials teach; returns the EPCs whose learned values changed.
pub async fn update(
    conn: &mut AnyConnection,
    groups: &BTreeSet<TrialGroup>,
) -> sqlx::Result<BTreeSet<Epc>> {
    let mut changed = BTreeSet::new();
    for group in groups {
        if group.relearn && update_learned(conn, group).await? {
            let data = json!({ "epc": group.epc.as_hex(), "robot_class": class_in_feed(group.robot_class.as_deref()) });
            events::append(conn, EventKind::LearnedChanged, data).await?;
            changed.insert(group.epc.clone());
        }
    }
    // Colour is learned per tag and class, whatever the action.
    let colour_groups: BTreeSet<(&Epc, Option<&str>)> =
        groups.iter().filter(|g| g.relearn).map(|g| (&g.epc, g.robot_class.as_deref())).collect();
    for (epc, robot_class) in colour_groups {
        let change = colour::update(conn, epc, robot_class).await?;
        if change.tag || change.household {
            // A household's model is in every entry of the class: the caches forget them all.
            let data = json!({ "epc": epc.as_hex(), "robot_class": class_in_feed(robot_class), "household": change.household });
            events::append(conn, EventKind::LearnedChanged, data).await?;
            changed.insert(epc.clone());
        }
    }
    // Size is learned per tag, whoever measured it: a tag is as large for every camera.
    let size_groups: BTreeSet<&Epc> = groups.iter().filter(|g| g.relearn).map(|g| &g.epc).collect();
    for epc in size_groups {
        if size::update(conn, epc).await? {
            let data = json!({ "epc": epc.as_hex(), "tag_size": true });
            events::append(conn, EventKind::LearnedChanged, data).await?;
            changed.insert(epc.clone());
        }
    }
    update_reliability(conn, groups).await?;
    Ok(changed)
}

async fn update_learned(conn: &mut AnyConnection, group: &TrialGroup) -> sqlx::Result<bool> {
    let Some(entry) = tags::entry_of(conn, &group.epc).await? else {
        return Ok(false);
    };
    let kind = entry
        .pointer(&format!("/behaviors/{}/behavior", escape(&group.behavior)))
        .and_then(Value::as_str)
        .and_then(|k| k.parse::<BehaviorKind>().ok());
    let mut changed = false;
    for rule in RULES.iter().filter(|rule| Some(rule.behavior) == kind) {
        let path = format!("$.measurements.{}", rule.measurement);
        let values = trial_counts::latest_measurements(
            conn,
            &path,
            &group.epc,
            group.robot_class.as_deref(),
            &group.behavior,
            LEARNING_WINDOW,
        )
        .await?;
        let pointer = format!("/behaviors/{}/{}", escape(&group.behavior), rule.parameter);
        let learned = median(values.clone()).map(|value| (value * 1000.0).round() / 1000.0);
        changed |= match learned.filter(|&value| within_bounds(&entry, &pointer, value)) {
            Some(rounded) => {
                learning::store_learned(
                    conn,
                    &group.epc,
                    group.robot_class.as_deref(),
                    &pointer,
                    rounded,
                    values.len() as i64,
                )
                .await?
            }
            None => {
                learning::forget_learned(conn, &group.epc, group.robot_class.as_deref(), &pointer)
                    .await?
            }
        };
    }
    Ok(changed)
}

/// Whether the entry with `value` at `pointer` still meets its behaviour's schema: a learned
/// value outside the safe bounds (a robot reporting 50 m for a drawer) is not learned.
fn within_bounds(entry: &Value, pointer: &str, value: f64) -> bool {
    let mut candidate = entry.clone();
    let Some((parent, key)) = pointer.rsplit_once('/') else { return false };
    let Some(Value::Object(parent)) = candidate.pointer_mut(parent) else { return false };
    parent.insert(pps_schema::pointer::unescape(key), value.into());
    // Only the learned value is judged; the entry's other fields passed when it was stored.
    let fits = match pps_schema::validate_tag(&candidate) {
        Ok(()) => true,
        Err(errors) => errors.at(pointer).next().is_none(),
    };
    if !fits {
        tracing::warn!(
            pointer,
            value,
            "a learned value is outside its behaviour's bounds; not learned"
        );
    }
    fits
}

/// Judges every group's reliability anew, in two statements whatever the batch's size (the
/// batch holds the write lock meanwhile), and stores and announces the verdicts that changed.
async fn update_reliability(
    conn: &mut AnyConnection,
    groups: &BTreeSet<TrialGroup>,
) -> sqlx::Result<()> {
    // Groups that differ only in behaviour share one verdict.
    let keys: BTreeSet<(&Epc, &str, Option<&str>)> =
        groups.iter().map(|g| (&g.epc, g.action.as_str(), g.robot_class.as_deref())).collect();
    let keys: Vec<GroupKey<'_>> = keys
        .into_iter()
        .map(|(epc, action, robot_class)| GroupKey { epc, action, robot_class })
        .collect();
    let outcomes = trial_counts::latest_outcomes(
        conn,
        &keys,
        RELIABILITY_WINDOW,
        &CountedPurposes::real_use(),
    )
    .await?;
    let before = learning::reliabilities(conn, &keys).await?;
    for ((key, (attempts, successes)), before) in keys.iter().zip(outcomes).zip(before) {
        let reliable = is_reliable(attempts, successes);
        // No row means "not reliable": a group stays rowless (and costs no write) until it
        // first becomes reliable.
        if before.unwrap_or(false) == reliable {
            continue;
        }
        learning::store_reliability(conn, key.epc, key.action, key.robot_class, reliable).await?;
        let data = json!({
            "epc": key.epc,
            "action": key.action,
            "robot_class": class_in_feed(key.robot_class),
            "reliable": reliable,
            "attempts": attempts,
            "successes": successes,
        });
        events::append(conn, EventKind::ReliabilityChanged, data).await?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_reliability_rule() {
        assert_eq!(median(vec![]), None);
        assert_eq!(median(vec![0.3, 0.1, 0.2]), Some(0.2));
        assert_eq!(median(vec![0.4, 0.1, 0.2, 0.3]), Some(0.25));
        assert!(!is_reliable(19, 19));
        assert!(is_reliable(20, 18));
        assert!(!is_reliable(20, 17));
        assert!(is_reliable(50, 45));
    }
}
