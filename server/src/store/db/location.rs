//! Where the registry's database lives: a SQLite file (the embedded default) or a PostgreSQL
//! database several replicas share. `--db` and `PPS_DB` take either spelling.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The database `--db` names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// A SQLite file, created when missing.
    File(PathBuf),
    /// `postgres://USER[:PASSWORD]@HOST[:PORT]/DB`, as libpq spells it.
    Postgres(String),
}

impl Location {
    /// The location as `--db` takes it, password included (for starting a process on it).
    pub fn as_db_arg(&self) -> String {
        match self {
            Self::File(path) => path.display().to_string(),
            Self::Postgres(url) => url.clone(),
        }
    }

    /// The SQLite file, if the database is one.
    pub fn file(&self) -> Option<&Path> {
        match self {
            Self::File(path) => Some(path),
            Self::Postgres(_) => None,
        }
    }
}

impl FromStr for Location {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        if text.starts_with("postgres://") || text.starts_with("postgresql://") {
            let url = url::Url::parse(text).map_err(|error| {
                format!(
                    "{} is not a PostgreSQL URL ({error}); write postgres://USER@HOST/DB",
                    redact(text)
                )
            })?;
            if url.path().trim_start_matches('/').is_empty() {
                return Err(format!(
                    "{} names no database; write postgres://USER@HOST/DB",
                    redact(text)
                ));
            }
            return Ok(Self::Postgres(text.to_owned()));
        }
        if let Some((scheme, _)) = text.split_once("://") {
            return Err(format!(
                "{scheme}:// is not a database the registry speaks: give a SQLite file's path or \
                 a postgres:// URL"
            ));
        }
        if text.is_empty() {
            return Err("the database path is empty".into());
        }
        Ok(Self::File(PathBuf::from(text)))
    }
}

impl fmt::Display for Location {
    /// The file's path, or the URL without its password: fit for logs and messages.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::File(path) => write!(f, "{}", path.display()),
            Self::Postgres(url) => f.write_str(&redact(url)),
        }
    }
}

/// `url` with any password replaced by `***`.
fn redact(url: &str) -> String {
    match url::Url::parse(url) {
        Ok(mut parsed) if parsed.password().is_some() => {
            let _ = parsed.set_password(Some("***"));
            parsed.to_string()
        }
        Ok(_) => url.to_owned(),
        Err(_) => "the URL given".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_and_urls_are_told_apart() {
        assert_eq!("pps.db".parse(), Ok(Location::File("pps.db".into())));
        assert_eq!(
            "postgres://pps@127.0.0.1:5432/registry".parse(),
            Ok(Location::Postgres("postgres://pps@127.0.0.1:5432/registry".into()))
        );
        assert!("postgresql://pps@db/registry".parse::<Location>().is_ok());
    }

    #[test]
    fn bad_spellings_say_what_to_write() {
        let error = "mysql://x@y/z".parse::<Location>().unwrap_err();
        assert!(error.contains("mysql:// is not a database"), "{error}");
        let error = "postgres://pps@127.0.0.1".parse::<Location>().unwrap_err();
        assert!(error.contains("names no database"), "{error}");
        assert!("".parse::<Location>().is_err());
    }

    #[test]
    fn passwords_stay_out_of_messages() {
        let location: Location = "postgres://pps:hunter2@db:5432/registry".parse().unwrap();
        assert_eq!(location.to_string(), "postgres://pps:***@db:5432/registry");
        let error = "postgres://pps:hunter2@db".parse::<Location>().unwrap_err();
        assert!(!error.contains("hunter2"), "{error}");
    }
}
