//! What a command other than `serve` and `migrate` says when its `--db` names no registry:
//! where it looked, as an absolute path, and how to make one.

use std::path::Path;

use super::Location;

/// The sentence for a SQLite file that does not exist.
pub(super) fn sqlite(path: &Path) -> String {
    let shown = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
    let shown = shown.display();
    format!(
        "there is no database at {shown}; create it with `pps-server migrate --db {shown}` (or \
         start `pps-server serve` there), or point --db or PPS_DB at an existing one"
    )
}

/// The sentence for a PostgreSQL database that holds no registry yet.
pub(super) fn postgres(location: &Location) -> String {
    format!(
        "the PostgreSQL database {location} holds no registry yet; create its tables with \
         `pps-server migrate --db URL` (or start `pps-server serve` on it), or point --db or \
         PPS_DB at the right database"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_the_absolute_path_and_the_command_that_creates_it() {
        let message = sqlite(Path::new("pps.bd"));
        let absolute = std::env::current_dir().unwrap().join("pps.bd");
        assert!(message.starts_with(&format!("there is no database at {}; ", absolute.display())));
        assert!(message.contains(&format!("pps-server migrate --db {}", absolute.display())));
    }

    #[test]
    fn never_shows_a_password() {
        let location: Location = "postgres://pps:hunter2@db/registry".parse().unwrap();
        let message = postgres(&location);
        assert!(message.contains("postgres://pps:***@db/registry"), "{message}");
        assert!(!message.contains("hunter2"));
    }
}
