//! Keeping every trial for good while its raw force samples and its pictures age out.
//!
//! Pictures: each tag keeps the newest N (by the trials' arrival order); an older picture's
//! bytes are removed, its trial and its digest stay (see [`keep_newest_pictures`]).
//!
//! A trial may carry thousands of finger force-torque samples; after some days only their
//! summary is worth the space. Thinning replaces the stored `forces` array with `[]` and puts
//! the summary, when it was thinned and the SHA-256 of the trial as submitted into
//! `measurements.forces_thinned`, so a robot that re-sends an old trial (its outbox after a long
//! outage) is still recognised as repeating it. Thinning must never delete a trial or change
//! anything else in it; trials are picked by the registry's `received_at`, not by the robot's
//! clock.

use std::time::Duration;

use serde::Serialize;
use serde_json::{Value, json};
use sha2::{Digest, Sha256};

use crate::clock::{self, Clock};
use crate::store::db::Db;
use crate::store::{pictures, trials};
use time::OffsetDateTime;

/// The key in `measurements` that marks a thinned trial and holds its summary.
pub const THINNED_KEY: &str = "forces_thinned";
/// Trials rewritten per write transaction, so robots' trial writes never wait long.
const BATCH: u32 = 50;
const EVERY: Duration = Duration::from_secs(24 * 3600);

/// The longest age accepted: a century, well inside the calendar's range.
pub const MAX_AGE_DAYS: u32 = 36_500;

/// How long ago a trial must have been received before its force samples are thinned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Age {
    pub days: u32,
}

impl Age {
    /// Trials received before this moment are old enough at `now`.
    fn cutoff(self, now: OffsetDateTime) -> OffsetDateTime {
        let ago = time::Duration::days(self.days.into());
        // Beyond the calendar nothing is that old: the epoch is as good a cutoff as any.
        now.checked_sub(ago).unwrap_or(OffsetDateTime::UNIX_EPOCH)
    }
}

/// What one thinning pass did.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct ThinReport {
    pub trials: u64,
    pub samples: u64,
}

/// The force samples of one trial in a few numbers; newtons are the force vector's magnitude.
#[derive(Debug, Default, Clone, Copy, PartialEq, Serialize)]
pub struct ForceSummary {
    pub samples: u64,
    pub peak_n: Option<f64>,
    pub mean_n: Option<f64>,
    /// From the first sample to the last, in seconds.
    pub duration_s: Option<f64>,
}

impl ForceSummary {
    /// Summarises force samples as the trial schema defines them (`t`, `force: [fx, fy, fz]`).
    pub fn of_samples(samples: &[Value]) -> Self {
        let magnitudes: Vec<f64> = samples.iter().filter_map(magnitude).collect();
        let times: Vec<f64> =
            samples.iter().filter_map(|sample| sample.get("t").and_then(Value::as_f64)).collect();
        let span = |values: &[f64]| {
            let first = values.iter().copied().reduce(f64::min)?;
            values.iter().copied().reduce(f64::max).map(|last| last - first)
        };
        Self {
            samples: samples.len() as u64,
            peak_n: magnitudes.iter().copied().reduce(f64::max),
            mean_n: (!magnitudes.is_empty())
                .then(|| magnitudes.iter().sum::<f64>() / magnitudes.len() as f64),
            duration_s: span(&times),
        }
    }

    /// The summary of a trial as the API returns it: from its samples, or from what thinning
    /// kept of them.
    pub fn of_trial(trial: &Value) -> Self {
        let samples = trial.get("forces").and_then(Value::as_array).map_or(&[][..], Vec::as_slice);
        match trial.pointer(&format!("/measurements/{THINNED_KEY}")) {
            Some(kept) if samples.is_empty() => Self {
                samples: kept.get("samples").and_then(Value::as_u64).unwrap_or(0),
                peak_n: kept.get("peak_n").and_then(Value::as_f64),
                mean_n: kept.get("mean_n").and_then(Value::as_f64),
                duration_s: kept.get("duration_s").and_then(Value::as_f64),
            },
            _ => Self::of_samples(samples),
        }
    }
}

fn magnitude(sample: &Value) -> Option<f64> {
    let force = sample.get("force")?.as_array()?;
    let squares = force.iter().map(|c| c.as_f64().map(|c| c * c)).sum::<Option<f64>>()?;
    Some(squares.sqrt())
}

/// Replaces a stored trial's force samples by their summary; false when there is nothing to
/// thin (no samples, or already thinned).
pub fn thin(trial: &mut Value, thinned_at: &str) -> bool {
    let samples = match trial.get("forces").and_then(Value::as_array) {
        Some(samples) if !samples.is_empty() => samples,
        _ => return false,
    };
    // A robot's own measurement of this name is left alone, and so are its samples.
    if trial.pointer(&format!("/measurements/{THINNED_KEY}")).is_some() {
        return false;
    }
    let summary = ForceSummary::of_samples(samples);
    let mut kept = serde_json::to_value(summary).unwrap_or_else(|_| json!({}));
    kept["thinned_at"] = thinned_at.into();
    kept["submitted_sha256"] = submission_digest(trial).into();
    let Some(object) = trial.as_object_mut() else { return false };
    object.insert("forces".into(), json!([]));
    let measurements = object.entry("measurements").or_insert_with(|| json!({}));
    match measurements.as_object_mut() {
        Some(measurements) => {
            measurements.insert(THINNED_KEY.into(), kept);
            true
        }
        None => false,
    }
}

/// Whether `submitted` is the trial stored as `stored`, also after `stored` was thinned:
/// the idempotency rule of `PUT /api/v1/trials/{id}`.
pub fn same_submission(stored: &Value, submitted: &Value) -> bool {
    stored == submitted
        || stored
            .pointer(&format!("/measurements/{THINNED_KEY}/submitted_sha256"))
            .and_then(Value::as_str)
            .is_some_and(|digest| digest == submission_digest(submitted))
}

/// SHA-256 of the trial with its keys sorted at every level: equal JSON, equal digest,
/// whatever order a robot's serializer wrote the keys in.
fn submission_digest(trial: &Value) -> String {
    let mut canonical = trial.clone();
    canonical.sort_all_objects();
    hex::encode(Sha256::digest(canonical.to_string().as_bytes()))
}

/// Thins every trial received longer ago than `age` at `now`; works while a server writes.
pub async fn thin_forces(db: &Db, age: Age, now: OffsetDateTime) -> anyhow::Result<ThinReport> {
    let cutoff = age.cutoff(now);
    let thinned_at = clock::format(now);
    let mut report = ThinReport::default();
    let mut after = 0;
    loop {
        let rows = trials::with_forces_received_before(db.reader(), cutoff, after, BATCH).await?;
        let Some(last) = rows.last() else { break };
        after = last.0;
        let mut tx = db.begin_write().await?;
        for (seq, stored) in &rows {
            let Ok(mut trial) = serde_json::from_str::<Value>(stored) else { continue };
            let samples = trial.get("forces").and_then(Value::as_array).map_or(0, Vec::len);
            if thin(&mut trial, &thinned_at)
                && trials::replace_body(&mut tx, *seq, stored, &trial.to_string()).await?
            {
                report.trials += 1;
                report.samples += samples as u64;
            }
        }
        tx.commit().await?;
    }
    Ok(report)
}

/// Removes the bytes of every tag's pictures beyond its newest `keep`; returns how many. New
/// pictures apply the rule as they arrive, so this pass matters when `keep` was lowered.
pub async fn keep_newest_pictures(db: &Db, keep: u32, now: OffsetDateTime) -> anyhow::Result<u64> {
    let mut removed = 0;
    for epc in pictures::tags_over(db.reader(), keep).await? {
        let mut tx = db.begin_write().await?;
        removed += pictures::keep_newest(&mut tx, &epc, keep, now).await?;
        tx.commit().await?;
    }
    Ok(removed)
}

/// Applies the picture rule once now and then once a day, for as long as the runtime runs.
pub fn start_daily_pictures(db: Db, clock: Clock, keep: u32) {
    tokio::spawn(async move {
        let mut daily = tokio::time::interval(EVERY);
        loop {
            daily.tick().await;
            match keep_newest_pictures(&db, keep, clock.now()).await {
                Ok(0) => {}
                Ok(removed) => tracing::info!(removed, keep, "removed tags' older pictures"),
                Err(error) => tracing::warn!(%error, "could not remove tags' older pictures"),
            }
        }
    });
}

/// Thins once now and then once a day, for as long as the runtime runs.
pub fn start_daily(db: Db, clock: Clock, age: Age) {
    tokio::spawn(async move {
        let mut daily = tokio::time::interval(EVERY);
        loop {
            daily.tick().await;
            match thin_forces(&db, age, clock.now()).await {
                Ok(report) if report.trials > 0 => tracing::info!(
                    trials = report.trials,
                    samples = report.samples,
                    days = age.days,
                    "thinned the force samples of old trials"
                ),
                Ok(_) => {}
                Err(error) => tracing::warn!(%error, "could not thin old trials' force samples"),
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trial_with_forces() -> Value {
        json!({
            "id": "7d7f4c1e-2a51-4f3a-9a55-0b5f0e1f2a3b", "outcome": "success",
            "forces": [
                { "t": 0.5, "finger": "left", "force": [3.0, 4.0, 0.0] },
                { "t": 1.5, "finger": "right", "force": [0.0, 0.0, 1.0], "torque": [0.0, 0.0, 0.0] }
            ],
            "measurements": { "pulled_m": 0.2 }
        })
    }

    #[test]
    fn thinning_keeps_a_summary_and_everything_else() {
        let submitted = trial_with_forces();
        let mut stored = submitted.clone();
        assert!(thin(&mut stored, "2026-11-22T10:00:00.000Z"));
        assert_eq!(stored["forces"], json!([]));
        assert_eq!(stored["measurements"]["pulled_m"], 0.2);
        assert_eq!(stored["outcome"], "success");
        let kept = &stored["measurements"][THINNED_KEY];
        assert_eq!(kept["samples"], 2);
        assert_eq!(kept["peak_n"], 5.0);
        assert_eq!(kept["mean_n"], 3.0);
        assert_eq!(kept["duration_s"], 1.0);
        assert_eq!(ForceSummary::of_trial(&stored), ForceSummary::of_trial(&submitted));
        assert!(!thin(&mut stored, "2026-11-23T10:00:00.000Z"), "thinning twice changes nothing");
    }

    #[test]
    fn a_thinned_trial_still_recognises_its_retry_and_only_that() {
        let submitted = trial_with_forces();
        let mut stored = submitted.clone();
        thin(&mut stored, "2026-11-22T10:00:00.000Z");
        assert!(same_submission(&stored, &submitted));
        let reordered: Value = serde_json::from_str(
            r#"{"measurements": {"pulled_m": 0.2}, "outcome": "success",
                "id": "7d7f4c1e-2a51-4f3a-9a55-0b5f0e1f2a3b", "forces": [
                { "finger": "left", "t": 0.5, "force": [3.0, 4.0, 0.0] },
                { "t": 1.5, "finger": "right", "force": [0.0, 0.0, 1.0], "torque": [0.0, 0.0, 0.0] }]}"#,
        )
        .unwrap();
        assert!(same_submission(&stored, &reordered));
        let mut other = submitted.clone();
        other["forces"][1]["force"][2] = json!(1.5);
        assert!(!same_submission(&stored, &other), "a changed sample is another trial");
        assert!(!same_submission(&submitted, &other));
    }

    #[test]
    fn a_robots_own_measurement_of_that_name_is_not_overwritten() {
        let mut trial = trial_with_forces();
        trial["measurements"][THINNED_KEY] = json!("the robot's");
        assert!(!thin(&mut trial, "2026-11-22T10:00:00.000Z"));
        assert_eq!(trial["forces"].as_array().unwrap().len(), 2);
    }

    #[test]
    fn no_samples_no_numbers() {
        assert_eq!(
            ForceSummary::of_samples(&[]),
            ForceSummary { samples: 0, peak_n: None, mean_n: None, duration_s: None }
        );
    }
}
