//! The id of a robot class (`el-e`) or of one robot (`el-e-1`).
//!
//! The grammar here is the one `robot.schema.json#/$defs/robot_id` states; a test keeps them
//! equal.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The longest robot id, in characters.
const MAX_LEN: usize = 63;

/// A robot class or robot id: lower-case ASCII letters, digits, `.`, `_` and `-`, starting
/// with a letter or digit, 1 to 63 characters. Safe in URL paths and log lines as is.
#[derive(Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct RobotId(String);

/// Why a string is not a robot id.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RobotIdError {
    #[error("a robot id must not be empty")]
    Empty,
    #[error("a robot id has at most {MAX_LEN} characters; this one has {0}")]
    TooLong(usize),
    #[error("a robot id starts with a lower-case letter or a digit, not {0:?}")]
    BadStart(char),
    #[error("a robot id is lower-case: write {suggestion:?} instead")]
    UpperCase { suggestion: String },
    #[error(
        "a robot id holds lower-case letters, digits, '.', '_' and '-': \
         {found:?} at position {position} is not allowed"
    )]
    BadChar { found: char, position: usize },
}

impl RobotId {
    /// Parses `input` without trimming or case-folding: an id is compared byte for byte, so
    /// silently changing it would bind a token to a robot nobody named.
    pub fn parse(input: &str) -> Result<Self, RobotIdError> {
        let first = input.chars().next().ok_or(RobotIdError::Empty)?;
        let len = input.chars().count();
        if len > MAX_LEN {
            return Err(RobotIdError::TooLong(len));
        }
        if input.chars().any(|c| c.is_ascii_uppercase()) {
            let lower = input.to_ascii_lowercase();
            if Self::parse(&lower).is_ok() {
                return Err(RobotIdError::UpperCase { suggestion: lower });
            }
        }
        if !(first.is_ascii_lowercase() || first.is_ascii_digit()) {
            return Err(RobotIdError::BadStart(first));
        }
        let allowed = |c: char| c.is_ascii_lowercase() || c.is_ascii_digit() || ".-_".contains(c);
        if let Some((position, found)) = input.chars().enumerate().find(|&(_, c)| !allowed(c)) {
            return Err(RobotIdError::BadChar { found, position });
        }
        Ok(Self(input.to_owned()))
    }

    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for RobotId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::str::FromStr for RobotId {
    type Err = RobotIdError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s)
    }
}

impl AsRef<str> for RobotId {
    fn as_ref(&self) -> &str {
        &self.0
    }
}

impl Serialize for RobotId {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.0)
    }
}

impl<'de> Deserialize<'de> for RobotId {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        Self::parse(&text).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_classes_and_robots() {
        for id in ["el-e", "el-e-1", "pr2", "0", "stretch.re2_7", &"a".repeat(63)] {
            assert_eq!(RobotId::parse(id).map(|r| r.to_string()), Ok(id.to_owned()));
        }
    }

    #[test]
    fn rejects_with_a_reason_a_person_can_act_on() {
        assert_eq!(RobotId::parse(""), Err(RobotIdError::Empty));
        assert_eq!(RobotId::parse(&"a".repeat(64)), Err(RobotIdError::TooLong(64)));
        assert_eq!(RobotId::parse("-el-e"), Err(RobotIdError::BadStart('-')));
        assert_eq!(RobotId::parse(".hidden"), Err(RobotIdError::BadStart('.')));
        assert_eq!(RobotId::parse("el e"), Err(RobotIdError::BadChar { found: ' ', position: 2 }));
        assert_eq!(
            RobotId::parse("el-e/1"),
            Err(RobotIdError::BadChar { found: '/', position: 4 })
        );
        let upper = RobotId::parse("EL-E-1").unwrap_err();
        assert_eq!(upper, RobotIdError::UpperCase { suggestion: "el-e-1".into() });
        assert!(upper.to_string().contains("\"el-e-1\""), "{upper}");
    }

    #[test]
    fn upper_case_with_other_faults_reports_the_first_fault() {
        assert_eq!(RobotId::parse("EL E"), Err(RobotIdError::BadStart('E')));
    }

    #[test]
    fn serde_parses_at_the_boundary() {
        let id: RobotId = serde_json::from_str("\"el-e-1\"").unwrap();
        assert_eq!(serde_json::to_string(&id).unwrap(), "\"el-e-1\"");
        assert!(serde_json::from_str::<RobotId>("\"El-E\"").is_err());
    }

    proptest::proptest! {
        /// The schema and the parser must accept exactly the same ids, or an id stored through
        /// one would be refused by the other.
        #[test]
        fn agrees_with_the_schema_grammar(id in "[a-zA-Z0-9._ /-]{0,66}") {
            let robot = serde_json::json!({"id": id, "name": "robot", "capabilities": []});
            let schema_accepts = crate::validate::validate_robot(&robot).is_ok();
            proptest::prop_assert_eq!(schema_accepts, RobotId::parse(&id).is_ok());
        }
    }
}
