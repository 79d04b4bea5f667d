//! Files in the robot's state directory are replaced whole: written beside their place and
//! renamed over it, so a crash leaves the old file or the new one, never half of either.

use std::fs;
use std::io::Write;
use std::path::Path;

/// Replaces `path` with `bytes` (a cache: losing the newest version to a power cut is fine).
pub fn replace(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let temporary = path.with_extension("tmp");
    fs::write(&temporary, bytes)?;
    fs::rename(&temporary, path)
}

/// Replaces `path` with `bytes` and waits until the disk has both the file and its name (a
/// record that must survive a power cut, such as a trial not yet uploaded).
pub fn replace_durably(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let temporary = path.with_extension("tmp");
    let mut file = fs::File::create(&temporary)?;
    file.write_all(bytes)?;
    file.sync_all()?;
    fs::rename(&temporary, path)?;
    // The rename is durable only once the directory itself is synced.
    match path.parent() {
        Some(dir) => fs::File::open(dir)?.sync_all(),
        None => Ok(()),
    }
}
