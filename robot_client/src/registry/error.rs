//! What can go wrong talking to the registry, with the server's problem+json parsed.

use serde::Deserialize;

/// An RFC 9457 problem document as the registry writes it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct Problem {
    pub status: u16,
    #[serde(default)]
    pub title: String,
    #[serde(default)]
    pub detail: String,
    #[serde(default)]
    pub errors: Vec<pps_schema::FieldError>,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}: {}", self.status, self.title, self.detail)?;
        for error in &self.errors {
            write!(f, "; {}: {}", error.pointer, error.message)?;
        }
        Ok(())
    }
}

#[derive(Debug, thiserror::Error)]
pub enum RegistryError {
    /// The registry answered with an error.
    #[error("the registry refused: {0}")]
    Refused(Problem),
    /// The registry could not be reached (and nothing cached could stand in). The message
    /// carries the causes, and so they are not also a `source()`.
    #[error("the registry is unreachable: {}", causes(.0))]
    Unreachable(reqwest::Error),
    /// The answer was not what the API promises.
    #[error("the registry's answer was not understood: {0}")]
    Malformed(String),
    /// The outbox or the entry cache could not be read or written. The reason is in the
    /// message, and so not also a `source()`: a command line printing the chain would say it
    /// twice.
    #[error("local storage failed: {0}")]
    Storage(std::io::Error),
}

impl From<std::io::Error> for RegistryError {
    fn from(error: std::io::Error) -> Self {
        RegistryError::Storage(error)
    }
}

/// An error with its causes, so "error sending request" says why (refused, TLS, timeout).
fn causes(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

impl RegistryError {
    /// The HTTP status the registry answered with, if it answered.
    pub fn status(&self) -> Option<u16> {
        match self {
            Self::Refused(problem) => Some(problem.status),
            _ => None,
        }
    }

    /// Reads a non-success response into an error, keeping what the server said.
    pub(crate) async fn from_response(response: reqwest::Response) -> Self {
        let status = response.status();
        let text = response.text().await.unwrap_or_default();
        let problem = serde_json::from_str::<Problem>(&text).unwrap_or_else(|_| Problem {
            status: status.as_u16(),
            title: status.canonical_reason().unwrap_or("error").to_owned(),
            detail: text.chars().take(300).collect(),
            errors: Vec::new(),
        });
        Self::Refused(problem)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_storage_failure_says_its_reason_once() {
        let reason = std::io::Error::from(std::io::ErrorKind::NotADirectory);
        let expected = reason.to_string();
        // The command lines print an error with its chain of causes.
        let message = format!("{:#}", anyhow::Error::from(RegistryError::from(reason)));
        assert_eq!(message.matches(&expected).count(), 1, "{message}");
    }
}
