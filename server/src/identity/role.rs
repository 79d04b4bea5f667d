//! The roles of DESIGN §4: who may do what.

use std::fmt;

/// A credential's role.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize, clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    Admin,
    Caretaker,
    Robot,
}

impl Role {
    pub const ALL: [Role; 3] = [Role::Admin, Role::Caretaker, Role::Robot];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::Admin => "admin",
            Self::Caretaker => "caretaker",
            Self::Robot => "robot",
        }
    }

    pub fn parse(text: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|role| role.as_str() == text)
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}
