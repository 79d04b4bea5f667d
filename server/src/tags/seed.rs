//! The paper's five devices, embedded from `seed_tags/`, and the JSON import/export of tags.

use anyhow::{Context, bail};
use pps_schema::{Epc, TagEntry};
use serde_json::Value;
use sqlx::AnyConnection;

use crate::accept::accept;
use crate::answers::tags::StoredTagAnswer;
use crate::error::ApiError;
use crate::store::WriteCondition;
use crate::store::db::Db;
use crate::store::tags;

/// `seed_tags/*.json`, compiled in so a bare binary can seed an empty registry.
const SEEDS: [(&str, &str); 5] = [
    ("light_switch.json", include_str!("../../../seed_tags/light_switch.json")),
    ("ada_light_switch.json", include_str!("../../../seed_tags/ada_light_switch.json")),
    ("lamp.json", include_str!("../../../seed_tags/lamp.json")),
    ("drawer.json", include_str!("../../../seed_tags/drawer.json")),
    ("trash_can.json", include_str!("../../../seed_tags/trash_can.json")),
];

/// Who the history names for seeded entries.
const SEED_AUTHOR: &str = "seed";

/// What an import or seed run did.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct ImportReport {
    pub created: usize,
    pub replaced: usize,
    pub unchanged: usize,
}

/// The seed entries, parsed.
pub fn seed_entries() -> anyhow::Result<Vec<Value>> {
    SEEDS
        .iter()
        .map(|(file, text)| serde_json::from_str(text).with_context(|| format!("seed_tags/{file}")))
        .collect()
}

/// The seed entry of a device kind (its `properties.type`); `-` and `_` spell a space.
pub fn template(kind: &str) -> anyhow::Result<Value> {
    let wanted = kind.trim().to_lowercase().replace(['-', '_'], " ");
    let seeds = seed_entries()?;
    let kinds: Vec<&str> =
        seeds.iter().filter_map(|entry| entry["properties"]["type"].as_str()).collect();
    let Some(found) = seeds.iter().find(|entry| entry["properties"]["type"] == wanted.as_str())
    else {
        bail!("there is no device kind {kind:?}; the kinds are: {}", kinds.join(", "));
    };
    Ok(found.clone())
}

/// Seeds the registry when it holds no tags at all; returns how many were loaded. The count is
/// taken under the write lock, so of several replicas starting together on one empty database
/// exactly one seeds it.
pub async fn seed_if_empty(db: &Db) -> anyhow::Result<usize> {
    let accepted = accept_all(seed_entries()?)?;
    let mut tx = db.begin_write().await?;
    if tags::count(&mut *tx).await? > 0 {
        return Ok(0);
    }
    let report = write_all(&mut tx, &accepted, SEED_AUTHOR).await?;
    tx.commit().await?;
    Ok(report.created)
}

/// Loads the seeds again: missing ones are created, changed ones restored to the seed.
pub async fn reload(db: &Db) -> anyhow::Result<ImportReport> {
    import(db, seed_entries()?, SEED_AUTHOR).await
}

/// Every tag with its read-only fields, as `export` prints it.
pub async fn export(db: &Db) -> anyhow::Result<Value> {
    let all = tags::all(db.reader()).await?;
    let answers: Vec<StoredTagAnswer> = all.iter().map(StoredTagAnswer::from).collect();
    Ok(serde_json::to_value(answers)?)
}

/// Imports entries (as exported, or plain entries): all are validated before anything is
/// written, and all are written in one transaction, so a bad file changes nothing.
pub async fn import(db: &Db, entries: Vec<Value>, by: &str) -> anyhow::Result<ImportReport> {
    let accepted = accept_all(entries)?;
    let mut tx = db.begin_write().await?;
    let report = write_all(&mut tx, &accepted, by).await?;
    tx.commit().await?;
    Ok(report)
}

/// An entry checked for import: its EPC, the entry, whether it is archived.
type Accepted = (Epc, Value, bool);

/// Every entry checked, or the first invalid one's problems, listed.
fn accept_all(entries: Vec<Value>) -> anyhow::Result<Vec<Accepted>> {
    let mut accepted = Vec::with_capacity(entries.len());
    for (index, value) in entries.into_iter().enumerate() {
        let archived = value.get("archived").and_then(Value::as_bool).unwrap_or(false);
        match accept::<TagEntry>(None, value) {
            Ok((epc, entry)) => accepted.push((epc, entry, archived)),
            Err(ApiError::Invalid(errors)) => {
                let listed: Vec<String> =
                    errors.iter().map(|e| format!("  {}: {}", e.pointer, e.message)).collect();
                bail!("entry {index} is not valid; nothing was imported:\n{}", listed.join("\n"));
            }
            Err(other) => bail!("entry {index}: {other}"),
        }
    }
    Ok(accepted)
}

/// Writes checked entries inside the caller's transaction, leaving unchanged ones alone.
async fn write_all(
    tx: &mut AnyConnection,
    accepted: &[Accepted],
    by: &str,
) -> anyhow::Result<ImportReport> {
    let mut report = ImportReport::default();
    for (epc, entry, archived) in accepted {
        let current = tags::current(tx, epc).await?;
        let unchanged =
            current.as_ref().is_some_and(|tag| tag.entry == *entry && tag.archived == *archived);
        if unchanged {
            report.unchanged += 1;
            continue;
        }
        let condition =
            if current.is_some() { WriteCondition::AnyRevision } else { WriteCondition::Absent };
        let (_, created) = tags::put_in(tx, epc, entry, &condition, by).await?;
        if *archived {
            tags::archive_in(tx, epc, &WriteCondition::AnyRevision, by).await?;
        }
        if created { report.created += 1 } else { report.replaced += 1 }
    }
    Ok(report)
}
