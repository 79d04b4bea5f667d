//! Where a task caretakers asked for stands (DESIGN §8), parsed once: the registry stores and
//! answers it, and a robot reads it back, as the same type.

use std::fmt;
use std::str::FromStr;

/// A task's state. A task is open while `Queued` or `Claimed`; the others are how it ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TaskState {
    /// Waiting for a robot that can do it.
    Queued,
    /// A robot holds it under a lease.
    Claimed,
    /// The robot's trial says it worked.
    Done,
    /// The robot's trial says it did not, or leases ran out too often.
    Failed,
    /// A person cancelled it, or it expired before a robot took it.
    Cancelled,
}

impl TaskState {
    pub const ALL: [TaskState; 5] =
        [Self::Queued, Self::Claimed, Self::Done, Self::Failed, Self::Cancelled];

    /// The states as the API spells them, in [`TaskState::ALL`]'s order.
    pub const NAMES: [&'static str; 5] = {
        let mut names = [""; 5];
        let mut i = 0;
        while i < names.len() {
            names[i] = Self::ALL[i].as_str();
            i += 1;
        }
        names
    };

    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Queued => "queued",
            Self::Claimed => "claimed",
            Self::Done => "done",
            Self::Failed => "failed",
            Self::Cancelled => "cancelled",
        }
    }

    /// Whether the task can still change hands or be cancelled.
    pub fn is_open(self) -> bool {
        matches!(self, Self::Queued | Self::Claimed)
    }
}

impl fmt::Display for TaskState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A state that is not one of [`TaskState::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?} is not a task state; one of queued, claimed, done, failed, cancelled")]
pub struct TaskStateError(pub String);

impl FromStr for TaskState {
    type Err = TaskStateError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|s| s.as_str() == text)
            .ok_or_else(|| TaskStateError(text.into()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_state_reads_back_as_itself_in_text_and_json() {
        for state in TaskState::ALL {
            assert_eq!(state.as_str().parse::<TaskState>(), Ok(state));
            assert_eq!(serde_json::to_value(state).unwrap(), state.as_str());
        }
        assert_eq!(
            "Queued".parse::<TaskState>().unwrap_err().to_string(),
            "\"Queued\" is not a task state; one of queued, claimed, done, failed, cancelled"
        );
    }
}
