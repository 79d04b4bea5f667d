//! The EPC: the key of every tag entry.
//!
//! An EPC is kept as the upper-case hex of the tag's EPC bank (whole 16-bit words, as Gen2 tags
//! store it), so any tag is a valid key. People may also type a GS1 EPC tag URI
//! (`urn:epc:tag:sgtin-96:3.0614141.812345.6789`); it is encoded to hex on parsing. 96-bit EPCs
//! of the SGTIN, SSCC, SGLN, GRAI, GIAI and GID schemes decode back to their tag URI and to the
//! pure-identity URI (`urn:epc:id:sgtin:0614141.812345.6789`) as the GS1 EPC Tag Data Standard
//! specifies; other EPCs simply have no URI.

mod scheme;
#[cfg(test)]
mod tests;

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// An EPC Gen2 identifier, stored as upper-case hex of whole 16-bit words.
#[derive(Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct Epc(String);

/// Why a string is not an EPC. Each message says what to change.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EpcError {
    #[error(
        "an EPC must not be empty: give its hex (e.g. 3074257BF7194E4000001A85) or a tag URI \
         (e.g. urn:epc:tag:sgtin-96:3.0614141.812345.6789)"
    )]
    Empty,
    /// `position` counts characters from 1, after surrounding whitespace is trimmed.
    #[error(
        "an EPC is hex digits (0-9, A-F) or a tag URI starting urn:epc:tag:, but {found:?} at \
         position {position} is not a hex digit"
    )]
    NotHex { found: char, position: usize },
    #[error(
        "an EPC has 4 to 124 hex digits in whole 16-bit words (a multiple of 4, e.g. 24 for a \
         96-bit EPC); this one has {0}"
    )]
    Length(usize),
    #[error(
        "{0:?} is a pure-identity URI, which has no filter value to write to a tag; give the EPC \
         as hex or as a tag URI (urn:epc:tag:..., e.g. urn:epc:tag:sgtin-96:3.0614141.812345.6789)"
    )]
    PureIdentityUri(String),
    #[error(
        "{0:?} is not an EPC tag URI; give the EPC as hex or as a URI starting urn:epc:tag: \
         (e.g. urn:epc:tag:sgtin-96:3.0614141.812345.6789)"
    )]
    NotTagUri(String),
    #[error(
        "the EPC scheme {0:?} cannot be encoded here: tag URIs may use sgtin-96, sscc-96, \
         sgln-96, grai-96, giai-96 or gid-96; give any other EPC as hex"
    )]
    UnknownScheme(String),
    #[error(
        "{scheme} tag URI: expected {expected} dot-separated fields after \"{scheme}:\" \
         ({layout}), found {found}"
    )]
    FieldCount { scheme: &'static str, expected: usize, found: usize, layout: &'static str },
    #[error("{scheme} tag URI: the filter value is one digit 0 to 7, not {found:?}")]
    Filter { scheme: &'static str, found: String },
    #[error("{scheme} tag URI: the {field} {}", not_digits(.found))]
    NotDigits { scheme: &'static str, field: &'static str, found: String },
    #[error(
        "{scheme} tag URI: the company prefix has 6 to 12 digits (its length selects the \
         partition), not {found}"
    )]
    CompanyPrefixDigits { scheme: &'static str, found: usize },
    #[error(
        "{scheme} tag URI: with a {company_prefix_digits}-digit company prefix the {field} has {}, \
         not {found}",
        digit_count(.expected)
    )]
    ReferenceDigits {
        scheme: &'static str,
        field: &'static str,
        company_prefix_digits: usize,
        expected: usize,
        found: usize,
    },
    #[error(
        "{scheme} tag URI: the {field} {found:?} must not start with 0 (the 96-bit encoding \
         stores a number, so leading zeros cannot be kept); write it without them"
    )]
    LeadingZeros { scheme: &'static str, field: &'static str, found: String },
    #[error(
        "{scheme} tag URI: the {field} {found} is too large; at most {max} fits in its {bits} bits"
    )]
    OutOfRange { scheme: &'static str, field: &'static str, found: String, max: u64, bits: u32 },
}

fn not_digits(found: &str) -> String {
    if found.is_empty() {
        "is missing: it must be decimal digits 0-9".to_owned()
    } else {
        format!("must be decimal digits 0-9, not {found:?}")
    }
}

fn digit_count(expected: &usize) -> String {
    match expected {
        0 => "no digits (leave it empty, so two dots meet)".to_owned(),
        1 => "exactly 1 digit".to_owned(),
        n => format!("exactly {n} digits"),
    }
}

/// At most 40 characters of user input, so an error never echoes a huge request back.
fn excerpt(text: &str) -> String {
    const MAX: usize = 40;
    match text.char_indices().nth(MAX) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_owned(),
    }
}

impl Epc {
    /// Parses hex (4..=124 digits, a multiple of 4, any case) or a GS1 EPC tag URI of one of
    /// the six 96-bit schemes; surrounding whitespace is ignored.
    pub fn parse(input: &str) -> Result<Self, EpcError> {
        let input = input.trim();
        if input.is_empty() {
            return Err(EpcError::Empty);
        }
        if starts_with_ignore_case(input, "urn:") {
            return Self::parse_uri(input);
        }
        if let Some((index, found)) =
            input.chars().enumerate().find(|(_, c)| !c.is_ascii_hexdigit())
        {
            return Err(EpcError::NotHex { found, position: index + 1 });
        }
        let len = input.len();
        if !(4..=124).contains(&len) || !len.is_multiple_of(4) {
            return Err(EpcError::Length(len));
        }
        Ok(Self(input.to_ascii_uppercase()))
    }

    fn parse_uri(uri: &str) -> Result<Self, EpcError> {
        const TAG: &str = "urn:epc:tag:";
        if starts_with_ignore_case(uri, TAG) {
            return scheme::encode_tag_uri(&uri[TAG.len()..]).map(Self);
        }
        if starts_with_ignore_case(uri, "urn:epc:id:") {
            return Err(EpcError::PureIdentityUri(excerpt(uri)));
        }
        Err(EpcError::NotTagUri(excerpt(uri)))
    }

    /// Upper-case hex, as stored and returned by the registry.
    pub fn as_hex(&self) -> &str {
        &self.0
    }

    /// The GS1 pure-identity URI (`urn:epc:id:sgtin:0614141.812345.6789`) when the EPC is a
    /// valid SGTIN-96, SSCC-96, SGLN-96, GRAI-96, GIAI-96 or GID-96 encoding.
    pub fn pure_identity_uri(&self) -> Option<String> {
        scheme::decode(&self.0).map(|decoded| decoded.pure_identity_uri())
    }

    /// The GS1 tag URI (`urn:epc:tag:sgtin-96:3.0614141.812345.6789`), which unlike the
    /// pure-identity URI keeps the filter value; [`Epc::parse`] turns it back into this EPC.
    pub fn tag_uri(&self) -> Option<String> {
        scheme::decode(&self.0).map(|decoded| decoded.tag_uri())
    }

    /// The scheme as named in tag URIs (`sgtin-96`, ..., `gid-96`) when the EPC decodes.
    pub fn scheme(&self) -> Option<&'static str> {
        scheme::decode(&self.0).map(|decoded| decoded.scheme.tag_name)
    }

    /// The filter value (0..=7) when the EPC decodes to a scheme that has one (all but GID-96).
    pub fn filter(&self) -> Option<u8> {
        scheme::decode(&self.0).and_then(|decoded| decoded.filter)
    }
}

fn starts_with_ignore_case(text: &str, prefix: &str) -> bool {
    text.get(..prefix.len()).is_some_and(|head| head.eq_ignore_ascii_case(prefix))
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
