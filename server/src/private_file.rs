//! Files the registry writes for its operator (the database, backups, exports) are created
//! readable by their owner alone: the database and its backups hold password and token hashes,
//! exports the household's data.

use std::fs::OpenOptions;
use std::os::unix::fs::OpenOptionsExt;

/// Open options that give a file they create the mode 0600.
pub fn options() -> OpenOptions {
    let mut options = OpenOptions::new();
    options.write(true).mode(0o600);
    options
}
