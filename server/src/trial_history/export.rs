//! `pps-server export-trials`: the trial history for analysis outside the registry, as JSON
//! lines or CSV, with the filters and meaning of `GET /api/v1/trials`.
//!
//! It pages through the same store query the API uses, so it works on a database of any size
//! while a server writes to it. It must never write to the database.
//!
//! With a pictures directory the export stands on its own: each trial's picture is written
//! there as a file named by the trial's id, and the export names that file (`picture_file`).
//! Files rather than bytes inside the lines: a folder of images opens in any viewer, joins to
//! the rows by id, and keeps the JSON lines and the CSV small enough for the tools they are for.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde_json::Value;
use sqlx::AnyPool;

use crate::answers::trials::StoredTrialAnswer;
use crate::store::pictures;
use crate::store::trials::{self, TrialRow};
use crate::trial_history::retention::ForceSummary;
use crate::trials::filter::TrialFilter;
use crate::trials::picture::PictureType;

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
pub const CSV_COLUMNS: [&str; 18] = [
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
    "picture_file",
];

/// What an export wrote.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Exported {
    pub trials: u64,
    /// Pictures written into the pictures directory.
    pub pictures: u64,
}

/// Writes every trial `filter` selects to `out`, oldest first, and with `pictures_dir` each
/// one's picture into that directory (made if missing).
pub async fn export_trials(
    pool: &AnyPool,
    filter: &TrialFilter,
    format: TrialFormat,
    out: impl Write,
    pictures_dir: Option<&Path>,
) -> anyhow::Result<Exported> {
    if let Some(dir) = pictures_dir {
        std::fs::create_dir_all(dir).map_err(|e| {
            anyhow::anyhow!("cannot make the pictures directory {}: {e}", dir.display())
        })?;
    }
    let mut sink = match format {
        TrialFormat::Jsonl => Sink::Jsonl(out),
        TrialFormat::Csv => {
            let mut csv = csv::Writer::from_writer(out);
            csv.write_record(CSV_COLUMNS)?;
            Sink::Csv(Box::new(csv))
        }
    };
    let mut written = Exported::default();
    let mut after = 0;
    loop {
        let window = trials::Window { after, limit: PAGE, max_bytes: EXPORT_BYTES, forces: true };
        let (rows, cut_short) = trials::list(pool, filter, window).await?;
        for row in &rows {
            let picture = match pictures_dir {
                Some(dir) if row.has_picture => write_picture(pool, dir, row).await?,
                _ => None,
            };
            written.pictures += u64::from(picture.is_some());
            sink.write(row, pictures_dir.map(|_| picture.as_deref()))?;
            written.trials += 1;
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

/// Writes the trial's picture into `dir` as `<trial id>.png` or `.jpg`; its path, or `None`
/// when retention has removed the bytes since the trial was listed.
async fn write_picture(
    pool: &AnyPool,
    dir: &Path,
    row: &TrialRow,
) -> anyhow::Result<Option<String>> {
    let Some(stored) = pictures::get(pool, &row.id).await? else { return Ok(None) };
    let Some(bytes) = stored.bytes else { return Ok(None) };
    let extension = match PictureType::from_content_type(&stored.media_type) {
        Some(PictureType::Jpeg) => "jpg",
        _ => "png",
    };
    let path: PathBuf = dir.join(format!("{}.{extension}", row.id));
    let mut file = crate::private_file::options()
        .create(true)
        .truncate(true)
        .open(&path)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    file.write_all(&bytes).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    Ok(Some(path.display().to_string()))
}

impl<W: Write> Sink<W> {
    /// Writes one trial; `picture_file` is `None` when no pictures directory was asked for,
    /// else the file its picture went to, if it has one.
    fn write(&mut self, row: &TrialRow, picture_file: Option<Option<&str>>) -> anyhow::Result<()> {
        let mut trial = serde_json::to_value(StoredTrialAnswer::from(row))?;
        match self {
            Self::Jsonl(out) => {
                if let (Some(file), Some(object)) = (picture_file, trial.as_object_mut()) {
                    object.insert("picture_file".into(), file.map_or(Value::Null, Value::from));
                }
                serde_json::to_writer(&mut *out, &trial)?;
                out.write_all(b"\n")?;
            }
            Self::Csv(csv) => {
                csv.write_record(csv_row(row, &trial, picture_file.flatten().unwrap_or_default()))?
            }
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

fn csv_row(row: &TrialRow, trial: &Value, picture_file: &str) -> [String; CSV_COLUMNS.len()] {
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
        crate::clock::format(row.received_at),
        row.seq.to_string(),
        number(duration),
        forces.samples.to_string(),
        number(forces.peak_n),
        trial.get("measurements").map(Value::to_string).unwrap_or_else(|| "{}".into()),
        row.purpose.clone(),
        picture_file.to_owned(),
    ]
}
