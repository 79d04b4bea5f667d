//! `pps-server seed`, `export`, `import` and `tags template`: the tags in and out as one JSON
//! array, and one entry to start from.

use std::io::{Read, Write};
use std::path::PathBuf;

use anyhow::{Context, bail};

use pps_schema::Epc;

use crate::store::db::Db;
use crate::tags::seed;

/// Loads the paper's five devices again.
pub(super) async fn seed(db: &Db) -> anyhow::Result<()> {
    let report = seed::reload(db).await?;
    eprintln!(
        "seeded: {} created, {} restored, {} unchanged",
        report.created, report.replaced, report.unchanged
    );
    Ok(())
}

/// Prints every tag, or writes them to `out` and says so.
pub(super) async fn export(db: &Db, out: Option<PathBuf>) -> anyhow::Result<()> {
    let tags = seed::export(db).await?;
    let count = tags.as_array().map_or(0, Vec::len);
    let text = serde_json::to_string_pretty(&tags)?;
    match out {
        Some(path) => {
            crate::private_file::options()
                .create(true)
                .truncate(true)
                .open(&path)
                .and_then(|mut file| file.write_all((text + "\n").as_bytes()))
                .with_context(|| format!("cannot write {}", path.display()))?;
            eprintln!("wrote {count} tags to {}", path.display());
            Ok(())
        }
        None => {
            println!("{text}");
            Ok(())
        }
    }
}

pub(super) async fn import(db: &Db, file: Option<PathBuf>) -> anyhow::Result<()> {
    let text = match &file {
        Some(path) => std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?,
        None => {
            let mut text = String::new();
            std::io::stdin().read_to_string(&mut text)?;
            text
        }
    };
    let value: serde_json::Value = serde_json::from_str(&text).context("the input is not JSON")?;
    let serde_json::Value::Array(entries) = value else {
        bail!("the input must be a JSON array of tag entries, as `pps-server export` prints");
    };
    let report = seed::import(db, entries, "import").await?;
    eprintln!(
        "imported: {} created, {} replaced, {} unchanged",
        report.created, report.replaced, report.unchanged
    );
    Ok(())
}

/// Prints the seed entry of a device `kind`, with a new EPC and name when given: an entry a
/// person can PUT without a copy of the repository at hand.
pub(super) fn template(kind: &str, epc: Option<&str>, name: Option<&str>) -> anyhow::Result<()> {
    let mut entry = seed::template(kind)?;
    if let Some(epc) = epc {
        let epc = Epc::parse(epc).map_err(|error| anyhow::anyhow!("--epc {epc}: {error}"))?;
        entry["epc"] = epc.as_hex().into();
    }
    if let Some(name) = name {
        entry["properties"]["name"] = name.into();
    }
    println!("{}", serde_json::to_string_pretty(&entry)?);
    Ok(())
}
