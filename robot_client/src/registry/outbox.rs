//! The trial outbox: every trial is written to disk before anything tries to upload it, so a
//! robot with no server, or one that crashes or restarts, loses no trial.
//!
//! One file per trial, named so that a directory listing is the order of recording. Files are
//! written to a temporary name, synced, then renamed, so a crash leaves either the whole trial
//! or nothing. Trials the registry refuses for good are moved to `rejected/` with the reason,
//! never deleted.
//!
//! A trial's picture waits beside it (the same name, `.png`), written before the trial so a
//! waiting trial always has its whole picture. It goes up after its trial and is forgotten
//! before it, so a robot that stops in between sends both again, and the registry answers the
//! repeats as retries: the picture arrives once.

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{SystemTime, UNIX_EPOCH};

use pps_schema::Trial;

use super::state_file;

#[derive(Debug, Clone)]
pub struct TrialOutbox {
    dir: PathBuf,
    /// Failed uploads in a row per waiting file, since this process opened the outbox.
    failures: Arc<Mutex<HashMap<PathBuf, u32>>>,
}

/// A trial waiting in the outbox.
#[derive(Debug, Clone)]
pub struct PendingTrial {
    pub path: PathBuf,
    pub trial: Trial,
    /// Its picture (PNG), when one waits with it.
    pub picture: Option<PathBuf>,
}

impl PendingTrial {
    /// The picture's bytes, when one waits with the trial.
    pub fn picture_bytes(&self) -> std::io::Result<Option<Vec<u8>>> {
        self.picture.as_ref().map(fs::read).transpose()
    }
}

impl TrialOutbox {
    /// Opens (creating) the outbox in `dir`, dropping half-written files from a crash.
    pub fn open(dir: impl Into<PathBuf>) -> std::io::Result<Self> {
        let dir = dir.into();
        fs::create_dir_all(dir.join("rejected"))?;
        for entry in fs::read_dir(&dir)? {
            let path = entry?.path();
            // A picture without its trial: the robot stopped before the trial was written.
            let orphan = path.extension().is_some_and(|e| e == "png")
                && !path.with_extension("json").exists();
            if path.extension().is_some_and(|e| e == "tmp") || orphan {
                fs::remove_file(path)?;
            }
        }
        Ok(Self { dir, failures: Arc::default() })
    }

    /// Stores a trial durably. Pushing a trial whose id is already waiting changes nothing.
    pub fn push(&self, trial: &Trial) -> std::io::Result<()> {
        self.push_with_picture(trial, None)
    }

    /// Stores a trial and its picture (PNG bytes) durably, the picture first.
    pub fn push_with_picture(&self, trial: &Trial, picture: Option<&[u8]>) -> std::io::Result<()> {
        let suffix = format!("-{}.json", trial.id);
        if self.files()?.iter().any(|path| path.to_string_lossy().ends_with(&suffix)) {
            return Ok(());
        }
        let nanos = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_nanos());
        let path = self.dir.join(format!("{nanos:020}{suffix}"));
        if let Some(picture) = picture {
            state_file::replace_durably(&path.with_extension("png"), picture)?;
        }
        state_file::replace_durably(&path, &serde_json::to_vec_pretty(trial)?)
    }

    /// Trials waiting for upload, oldest first. A file that cannot be read is set aside.
    pub fn pending(&self) -> std::io::Result<Vec<PendingTrial>> {
        let mut pending = Vec::new();
        for path in self.files()? {
            match fs::read(&path).ok().and_then(|bytes| serde_json::from_slice(&bytes).ok()) {
                Some(trial) => {
                    let picture = Some(path.with_extension("png")).filter(|p| p.exists());
                    pending.push(PendingTrial { path, trial, picture });
                }
                None => self.set_aside(&path, "the file is not a readable trial")?,
            }
        }
        Ok(pending)
    }

    pub fn len(&self) -> std::io::Result<usize> {
        Ok(self.files()?.len())
    }

    pub fn is_empty(&self) -> std::io::Result<bool> {
        Ok(self.len()? == 0)
    }

    /// The registry has the trial (and its picture, if one waited): forget them, the picture
    /// first, so a trial never waits without the picture it was recorded with.
    pub fn uploaded(&self, trial: &PendingTrial) -> std::io::Result<()> {
        self.failures.lock().unwrap_or_else(|e| e.into_inner()).remove(&trial.path);
        if let Some(picture) = &trial.picture {
            fs::remove_file(picture)?;
        }
        fs::remove_file(&trial.path)
    }

    /// The registry has the trial but refused its picture for good: keep the picture aside
    /// with the reason, and the trial no longer waits for it.
    pub fn reject_picture(&self, trial: &PendingTrial, reason: &str) -> std::io::Result<()> {
        if let Some(picture) = &trial.picture {
            self.set_aside(picture, reason)?;
        }
        self.failures.lock().unwrap_or_else(|e| e.into_inner()).remove(&trial.path);
        fs::remove_file(&trial.path)
    }

    /// The registry failed on the trial once more; returns how often in a row it has.
    pub fn failed_upload(&self, trial: &PendingTrial) -> u32 {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        let count = failures.entry(trial.path.clone()).or_insert(0);
        *count += 1;
        *count
    }

    /// The registry refused the trial for good: keep it aside with the reason, for a person.
    pub fn reject(&self, trial: &PendingTrial, reason: &str) -> std::io::Result<()> {
        self.failures.lock().unwrap_or_else(|e| e.into_inner()).remove(&trial.path);
        self.set_aside(&trial.path, reason)
    }

    /// Trials set aside, with why.
    pub fn rejected(&self) -> std::io::Result<Vec<(PathBuf, String)>> {
        let mut rejected = Vec::new();
        for entry in fs::read_dir(self.dir.join("rejected"))? {
            let path = entry?.path();
            if path.extension().is_some_and(|e| e == "json") {
                let reason = fs::read_to_string(path.with_extension("reason")).unwrap_or_default();
                rejected.push((path, reason));
            }
        }
        rejected.sort();
        Ok(rejected)
    }

    fn set_aside(&self, path: &Path, reason: &str) -> std::io::Result<()> {
        let name = path.file_name().unwrap_or_default();
        let target = self.dir.join("rejected").join(name);
        let is_trial = path.extension().is_some_and(|e| e == "json");
        let reason_file = if is_trial {
            target.with_extension("reason")
        } else {
            target.with_extension("png.reason")
        };
        fs::write(reason_file, reason)?;
        // A trial set aside keeps its picture beside it, for the person who looks.
        let picture = path.with_extension("png");
        if is_trial && picture.exists() {
            fs::rename(&picture, target.with_extension("png"))?;
        }
        fs::rename(path, &target)?;
        fs::File::open(&self.dir)?.sync_all()
    }

    fn files(&self) -> std::io::Result<Vec<PathBuf>> {
        let mut files = Vec::new();
        for entry in fs::read_dir(&self.dir)? {
            let path = entry?.path();
            if path.is_file() && path.extension().is_some_and(|e| e == "json") {
                files.push(path);
            }
        }
        files.sort();
        Ok(files)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn trial(n: u8) -> Trial {
        serde_json::from_value(serde_json::json!({
            "id": format!("00000000-0000-4000-8000-0000000000{n:02}"),
            "epc": "355AB1C60000002000000001", "robot": "el-e-1", "action": "on",
            "behavior": "push_top", "started_at": "2026-11-22T10:00:00Z",
            "finished_at": "2026-11-22T10:00:30Z", "outcome": "success"
        }))
        .unwrap()
    }

    #[test]
    fn trials_survive_reopening_in_order_and_once() {
        let dir = tempfile::tempdir().unwrap();
        let outbox = TrialOutbox::open(dir.path()).unwrap();
        for n in [3, 1, 2, 1] {
            outbox.push(&trial(n)).unwrap();
        }
        std::fs::write(dir.path().join("00000000000000000009-x.tmp"), b"{half").unwrap();
        let reopened = TrialOutbox::open(dir.path()).unwrap();
        let pending = reopened.pending().unwrap();
        let ids: Vec<String> =
            pending.iter().map(|p| p.trial.id.to_string()[34..].to_owned()).collect();
        assert_eq!(ids, ["03", "01", "02"], "recording order, each once");
        reopened.uploaded(&pending[0]).unwrap();
        reopened.reject(&pending[1], "409: another trial has this id").unwrap();
        assert_eq!(reopened.len().unwrap(), 1);
        let rejected = reopened.rejected().unwrap();
        assert_eq!(rejected.len(), 1);
        assert!(rejected[0].1.contains("409"));
    }

    #[test]
    fn a_picture_waits_with_its_trial_and_goes_with_it() {
        let dir = tempfile::tempdir().unwrap();
        let outbox = TrialOutbox::open(dir.path()).unwrap();
        outbox.push_with_picture(&trial(1), Some(b"picture one")).unwrap();
        outbox.push(&trial(2)).unwrap();
        // A picture whose trial was never written (the robot stopped in between) is dropped.
        std::fs::write(dir.path().join("00000000000000000009-x.png"), b"orphan").unwrap();
        let reopened = TrialOutbox::open(dir.path()).unwrap();
        let pending = reopened.pending().unwrap();
        assert_eq!(pending[0].picture_bytes().unwrap().as_deref(), Some(&b"picture one"[..]));
        assert_eq!(pending[1].picture_bytes().unwrap(), None);
        assert!(!dir.path().join("00000000000000000009-x.png").exists());
        reopened.uploaded(&pending[0]).unwrap();
        reopened.reject_picture(&pending[1], "no picture to reject").unwrap();
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert_eq!(left, ["rejected"], "trials and pictures gone together");
    }

    #[test]
    fn unreadable_files_are_set_aside_not_lost() {
        let dir = tempfile::tempdir().unwrap();
        let outbox = TrialOutbox::open(dir.path()).unwrap();
        std::fs::write(dir.path().join("00000000000000000001-broken.json"), b"not json").unwrap();
        assert!(outbox.pending().unwrap().is_empty());
        assert_eq!(outbox.rejected().unwrap().len(), 1);
    }
}
