//! `pps-server backup`: a consistent copy of a SQLite database.

use std::path::Path;

use crate::ops::backup;
use crate::store::db::Db;

pub(super) async fn backup(db: &Db, to: &Path, force: bool) -> anyhow::Result<()> {
    let report = backup::backup(db, to, force).await?;
    eprintln!(
        "backed up {} tags, {} trials and {} trial pictures to {} ({} bytes, integrity ok)",
        report.tags,
        report.trials,
        report.pictures,
        report.path.display(),
        report.bytes
    );
    Ok(())
}
