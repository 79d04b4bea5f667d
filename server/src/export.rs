//! `pps-server export-trials`: the trial history for analysis outside the registry, as JSON
//! lines or CSV, with the filters and meaning of `GET /api/v1/trials`.
//!
//! It pages through the same store query the API uses, so it works on a database of any size
//! while a server writes to it. It must never write to the database.

use std::io::Write;

use serde_json::Value;
use sqlx::AnyPool;

use crate::retention::ForceSummary;
use crate::store::trials::{self, TrialRow};
use crate::trial_filter::TrialFilter;

/// Trials read per query.
const PAGE: u32 = 500;
/// Stored trial bytes held at once while exporting.
const EXPORT_BYTES: usize = 16 << 20;

/// How trials are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrialFormat {
    /// One trial per line, exactly as the API returns it.
    Jsonl,
    /// One row per trial with flat columns (see [`CSV_COLUMNS`]).
    Csv,
}

/// The CSV header; `measurements` is the trial's measurements object as a JSON string.
pub const CSV_COLUMNS: [&str; 17] = [
    "id",
    "epc",
    "robot",
    "robot_class",
    "action",
    "behavior",
    "outcome",
    "confirmed",
    "started_at",
    "finished_at",
    "received_at",
    "seq",
    "duration_s",
    "force_samples",
    "peak_force_n",
    "measurements",
    "purpose",
];

/// Writes every trial `filter` selects to `out`, oldest first; returns how many.
pub async fn export_trials(
    pool: &AnyPool,
    filter: &TrialFilter,
    format: TrialFormat,
    out: impl Write,
) -> anyhow::Result<u64> {
    let mut sink = match format {
        TrialFormat::Jsonl => Sink::Jsonl(out),
        TrialFormat::Csv => {
            let mut csv = csv::Writer::from_writer(out);
            csv.write_record(CSV_COLUMNS)?;
            Sink::Csv(Box::new(csv))
        }
    };
    let mut written = 0;
    let mut after = 0;
    loop {
        let window = trials::Window { after, limit: PAGE, max_bytes: EXPORT_BYTES, forces: true };
        let (rows, cut_short) = trials::list(pool, filter, window).await?;
        for row in &rows {
            sink.write(row)?;
            written += 1;
        }
        match rows.last() {
            Some(last) if cut_short || rows.len() == PAGE as usize => after = last.seq,
            _ => break,
        }
    }
    sink.finish()?;
    Ok(written)
}

enum Sink<W: Write> {
    Jsonl(W),
    /// Boxed: the writer carries its buffer inline.
    Csv(Box<csv::Writer<W>>),
}

impl<W: Write> Sink<W> {
    fn write(&mut self, row: &TrialRow) -> anyhow::Result<()> {
        let trial = row.to_json();
        match self {
            Self::Jsonl(out) => {
                serde_json::to_writer(&mut *out, &trial)?;
                out.write_all(b"\n")?;
            }
            Self::Csv(csv) => csv.write_record(csv_row(row, &trial))?,
        }
        Ok(())
    }

    fn finish(self) -> anyhow::Result<()> {
        match self {
            Self::Jsonl(mut out) => out.flush()?,
            Self::Csv(mut csv) => csv.flush()?,
        }
        Ok(())
    }
}

fn csv_row(row: &TrialRow, trial: &Value) -> [String; CSV_COLUMNS.len()] {
    let text = |key: &str| trial.get(key).and_then(Value::as_str).unwrap_or_default().to_owned();
    let number = |value: Option<f64>| value.map(|v| v.to_string()).unwrap_or_default();
    let forces = ForceSummary::of_trial(trial);
    let (started_at, finished_at) = (text("started_at"), text("finished_at"));
    let duration = crate::clock::parse(&started_at)
        .zip(crate::clock::parse(&finished_at))
        .map(|(start, end)| (end - start).as_seconds_f64());
    [
        row.id.to_string(),
        row.epc.as_hex().to_owned(),
        row.robot.as_str().to_owned(),
        row.robot_class.clone().unwrap_or_default(),
        row.action.clone(),
        text("behavior"),
        row.outcome.clone(),
        row.confirmed.map(|c| c.to_string()).unwrap_or_default(),
        started_at,
        finished_at,
        row.received_at.clone(),
        row.seq.to_string(),
        number(duration),
        forces.samples.to_string(),
        number(forces.peak_n),
        trial.get("measurements").map(Value::to_string).unwrap_or_else(|| "{}".into()),
        row.purpose.clone(),
    ]
}
