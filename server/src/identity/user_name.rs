//! A login name, parsed at the boundary: what people type on a phone (a capital first letter,
//! stray spaces) becomes the one spelling the registry stores.

use std::fmt;

/// Longest login name, in characters.
pub const MAX_CHARS: usize = 64;

/// A valid, lower-case login name such as `anna` or `night.nurse`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct UserName(String);

impl UserName {
    /// Trims and lower-cases `text`, then checks it: letters a–z, digits, `.`, `_` and `-`,
    /// starting with a letter or digit.
    pub fn parse(text: &str) -> Result<Self, String> {
        let name = text.trim().to_lowercase();
        let mut chars = name.chars();
        match chars.next() {
            None => return Err("a user name cannot be empty".into()),
            Some(first) if !first.is_ascii_lowercase() && !first.is_ascii_digit() => {
                return Err(format!("a user name starts with a letter or digit, not {first:?}"));
            }
            Some(_) => {}
        }
        if let Some(bad) =
            chars.find(|c| !(c.is_ascii_lowercase() || c.is_ascii_digit() || "._-".contains(*c)))
        {
            return Err(format!(
                "a user name may hold only letters a-z, digits, '.', '_' and '-', not {bad:?}"
            ));
        }
        if name.chars().count() > MAX_CHARS {
            return Err(format!("a user name has at most {MAX_CHARS} characters"));
        }
        Ok(Self(name))
    }

    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for UserName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_normalised_and_checked() {
        assert_eq!(UserName::parse(" Anna ").unwrap().as_str(), "anna");
        assert_eq!(UserName::parse("night.nurse-2").unwrap().as_str(), "night.nurse-2");
        assert!(UserName::parse("").is_err());
        assert!(UserName::parse("-anna").is_err());
        assert!(UserName::parse("anna smith").is_err());
        assert!(UserName::parse("<img>").is_err());
        assert!(UserName::parse(&"a".repeat(MAX_CHARS + 1)).is_err());
        assert!(UserName::parse(&"a".repeat(MAX_CHARS)).is_ok());
    }
}
