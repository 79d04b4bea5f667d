//! `pps-server export-trials` and `thin-forces`: the trial history out, and kept small.

use anyhow::Context;

use super::{ExportTrialsArgs, FormatArg};
use crate::store::db::Db;
use crate::trial_history::export::{self, TrialFormat};
use crate::trial_history::retention::{self, Age};
use crate::trials::filter::{FilterText, TrialFilter};

pub(super) async fn export_trials(db: &Db, args: ExportTrialsArgs) -> anyhow::Result<()> {
    let filter = TrialFilter::parse(FilterText {
        epc: args.epc.as_deref(),
        robot: args.robot.as_deref(),
        action: args.action.as_deref(),
        outcome: args.outcome.as_deref(),
        since: args.since.as_deref(),
        purpose: args.purpose.as_deref(),
    })?;
    let format = match args.format {
        FormatArg::Jsonl => TrialFormat::Jsonl,
        FormatArg::Csv => TrialFormat::Csv,
    };
    let pictures = args.pictures.as_deref();
    let written = match &args.out {
        Some(path) => {
            let file = crate::private_file::options()
                .create(true)
                .truncate(true)
                .open(path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            let out = std::io::BufWriter::new(file);
            export::export_trials(db.reader(), &filter, format, out, pictures).await?
        }
        None => {
            let out = std::io::stdout().lock();
            export::export_trials(db.reader(), &filter, format, out, pictures).await?
        }
    };
    let to = args.out.as_ref().map(|p| format!(" to {}", p.display())).unwrap_or_default();
    match pictures {
        Some(dir) => eprintln!(
            "exported {} trials{to}, and {} pictures to {}",
            written.trials,
            written.pictures,
            dir.display()
        ),
        None => eprintln!("exported {} trials{to}", written.trials),
    }
    Ok(())
}

pub(super) async fn thin_forces(db: &Db, days: u32) -> anyhow::Result<()> {
    let report = retention::thin_forces(db, Age { days }, time::OffsetDateTime::now_utc()).await?;
    eprintln!(
        "thinned {} trials received more than {days} days ago ({} force samples replaced by \
         their summary)",
        report.trials, report.samples
    );
    Ok(())
}
