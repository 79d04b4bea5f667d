//! `pps-server backup`: a consistent copy of the live database, taken while the server serves.
//!
//! `VACUUM INTO` reads one snapshot of the database in a read transaction, so the copy holds
//! exactly the writes committed before it began, however many robots write meanwhile, and it
//! never blocks them. The copy is written beside the target under a temporary name, checked,
//! and only then renamed into place: a backup that stops half-way never looks like a backup.
//! This module must never write to the source database.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};

use crate::store::{self, db::Db};

/// What a backup holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BackupReport {
    pub path: PathBuf,
    pub bytes: u64,
    /// Tags, archived ones included.
    pub tags: i64,
    pub trials: i64,
    /// Trial pictures whose bytes the copy holds.
    pub pictures: i64,
}

/// What `backup` says on a PostgreSQL registry, whose own tools take consistent copies.
pub const NOT_ON_POSTGRES: &str = "backup copies a SQLite registry file; a PostgreSQL registry \
    is backed up with PostgreSQL's own pg_dump (for example pg_dump --format=custom --file \
    pps.dump DB), which takes one consistent snapshot while the replicas serve";

/// Copies the SQLite file `db` was opened from to `to`; an existing `to` is replaced only when
/// `replace` is set, and never when it is the database itself.
pub async fn backup(db: &Db, to: &Path, replace: bool) -> anyhow::Result<BackupReport> {
    let Some(source) = db.location().file() else {
        bail!("{NOT_ON_POSTGRES}");
    };
    if let Some(live) = live_file(source, to) {
        bail!("{} is {}; back it up to a file of its own", to.display(), live.what);
    }
    if to.exists() && !replace {
        bail!("{} already exists; choose a new file or pass --force to replace it", to.display());
    }
    if let Some(dir) = to.parent().filter(|dir| !dir.as_os_str().is_empty() && !dir.is_dir()) {
        bail!(
            "cannot write the backup {}: the directory {} does not exist",
            to.display(),
            dir.display()
        );
    }
    let partial = partial_path(to)?;
    let _ = std::fs::remove_file(&partial);
    // SQLite writes into an empty file it is given, keeping its owner-only mode.
    crate::private_file::options()
        .create_new(true)
        .open(&partial)
        .with_context(|| format!("cannot create the backup {}", partial.display()))?;
    let copied = async {
        store::backup::vacuum_into(db, &partial).await?;
        let report = inspect(&partial).await?;
        // On disk before it takes the final name, so a crash never leaves a torn "backup".
        std::fs::File::open(&partial)?.sync_all()?;
        std::fs::rename(&partial, to)
            .with_context(|| format!("cannot move the backup into place at {}", to.display()))?;
        Ok(BackupReport { path: to.to_owned(), ..report })
    }
    .await;
    if copied.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    copied
}

/// One of the files SQLite keeps a live database in.
#[derive(Debug, PartialEq, Eq)]
struct LiveFile {
    what: &'static str,
}

/// The files of a live database: the file itself, and beside it under the same name the journals
/// SQLite may create at any moment (replacing one loses every write it holds).
const LIVE_FILES: [(&str, &str); 4] = [
    ("", "the database itself"),
    ("-wal", "the live database's write-ahead log"),
    ("-shm", "the live database's shared-memory index"),
    ("-journal", "the live database's rollback journal"),
];

/// Which of the live database's files `to` names, if any: by path, after following symlinks
/// (also dangling ones, since a journal comes and goes) and `..`, or as another name (a hard
/// link) of an existing one.
fn live_file(source: &Path, to: &Path) -> Option<LiveFile> {
    let source = resolved(source);
    let target = resolved(to);
    LIVE_FILES.iter().find_map(|(suffix, what)| {
        let mut live = source.clone().into_os_string();
        live.push(suffix);
        let live = PathBuf::from(live);
        (live == target || same_inode(&live, &target)).then_some(LiveFile { what })
    })
}

/// `path` made absolute with every symlink followed, as far as the file system says; a name
/// that does not exist (yet) is resolved through its directory.
fn resolved(path: &Path) -> PathBuf {
    let mut path = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
    // As many links as the kernel follows before it calls it a loop.
    for _ in 0..40 {
        if let Ok(real) = path.canonicalize() {
            return real;
        }
        match std::fs::read_link(&path) {
            Ok(link) => path = path.parent().map_or(link.clone(), |dir| dir.join(link)),
            Err(_) => break,
        }
    }
    match (path.parent().and_then(|dir| dir.canonicalize().ok()), path.file_name()) {
        (Some(dir), Some(name)) => dir.join(name),
        _ => path,
    }
}

#[cfg(unix)]
fn same_inode(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => (a.dev(), a.ino()) == (b.dev(), b.ino()),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode(_: &Path, _: &Path) -> bool {
    false
}

/// The temporary name the copy is written under, in the target's directory so the final
/// rename cannot cross file systems.
fn partial_path(to: &Path) -> anyhow::Result<PathBuf> {
    let name = to
        .file_name()
        .with_context(|| format!("{} is not a file name to write a backup to", to.display()))?;
    let mut partial = name.to_os_string();
    partial.push(".partial");
    Ok(to.with_file_name(partial))
}

/// Checks a copy's integrity and counts what it holds.
async fn inspect(path: &Path) -> anyhow::Result<BackupReport> {
    let contents = match store::backup::inspect(path).await? {
        Ok(contents) => contents,
        Err(found) => {
            bail!("the backup {} failed its integrity check: {found}", path.display())
        }
    };
    let bytes = std::fs::metadata(path)?.len();
    let store::backup::Contents { tags, trials, pictures } = contents;
    Ok(BackupReport { path: path.to_owned(), bytes, tags, trials, pictures })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_live_database_and_its_journals_are_found_by_any_name() {
        let dir = tempfile::tempdir().unwrap();
        let db = dir.path().join("pps.db");
        std::fs::write(&db, "").unwrap();
        std::fs::write(dir.path().join("pps.db-wal"), "").unwrap();
        let elsewhere = dir.path().join("elsewhere");
        std::fs::create_dir(&elsewhere).unwrap();
        let linked_dir = dir.path().join("linked");
        std::os::unix::fs::symlink(dir.path(), &linked_dir).unwrap();
        let to_journal = elsewhere.join("to-journal");
        std::os::unix::fs::symlink("../pps.db-journal", &to_journal).unwrap();
        let hard = elsewhere.join("hard");
        std::fs::hard_link(dir.path().join("pps.db-wal"), &hard).unwrap();

        let what = |to: &Path| live_file(&db, to).map(|live| live.what);
        assert_eq!(what(&db), Some("the database itself"));
        assert_eq!(what(&dir.path().join("pps.db-wal")), Some(LIVE_FILES[1].1));
        assert_eq!(what(&elsewhere.join("../pps.db-shm")), Some(LIVE_FILES[2].1));
        assert_eq!(what(&linked_dir.join("pps.db-wal")), Some(LIVE_FILES[1].1));
        assert_eq!(what(&to_journal), Some(LIVE_FILES[3].1), "a link to a journal not there yet");
        assert_eq!(what(&hard), Some(LIVE_FILES[1].1), "another name of the WAL");
        assert_eq!(what(&dir.path().join("pps.db-wal.bak")), None);
        assert_eq!(what(&elsewhere.join("pps.db-wal")), None);
        assert_eq!(what(&dir.path().join("copy.db")), None);
    }
}
