//! Which trials a success rate counts, by why they were made. Real use always counts; an
//! experiment's or a test's trials only when someone asks (`?include=experiment,test`), since
//! they fail on purpose and would make a tag look worse than it is for the people it serves.

use pps_schema::Purpose;

/// The purposes a count takes in; always real use, in the schema's order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CountedPurposes(Vec<Purpose>);

impl Default for CountedPurposes {
    fn default() -> Self {
        Self::real_use()
    }
}

impl CountedPurposes {
    /// What learning, reliability and the stats count unless asked otherwise.
    pub fn real_use() -> Self {
        Self(vec![Purpose::Use])
    }

    /// Real use and the purposes `include` lists, comma-separated (`experiment,test`).
    pub fn including(include: &str) -> Result<Self, String> {
        let mut counted = vec![Purpose::Use];
        for word in include.split(',') {
            let purpose = Purpose::parse(word.trim()).ok_or_else(|| {
                format!(
                    "include lists the purposes to count beside real use, separated by commas \
                     (experiment, test); {word:?} is not one"
                )
            })?;
            counted.push(purpose);
        }
        counted.sort();
        counted.dedup();
        Ok(Self(counted))
    }

    pub fn purposes(&self) -> &[Purpose] {
        &self.0
    }

    pub fn counts(&self, purpose: Purpose) -> bool {
        self.0.contains(&purpose)
    }

    /// The purposes as one SQL parameter, a JSON array of their names.
    pub fn parameter(&self) -> String {
        serde_json::Value::from_iter(self.0.iter().map(|purpose| purpose.as_str())).to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_use_always_counts_and_the_others_on_request() {
        assert_eq!(CountedPurposes::default().purposes(), [Purpose::Use]);
        assert_eq!(CountedPurposes::default().parameter(), r#"["use"]"#);
        let all = CountedPurposes::including("test, experiment,test").unwrap();
        assert_eq!(all.purposes(), [Purpose::Use, Purpose::Experiment, Purpose::Test]);
        assert_eq!(all.parameter(), r#"["use","experiment","test"]"#);
        assert!(!CountedPurposes::including("experiment").unwrap().counts(Purpose::Test));
    }

    #[test]
    fn an_unknown_purpose_is_named() {
        let error = CountedPurposes::including("experiment,demo").unwrap_err();
        assert!(error.ends_with("\"demo\" is not one"), "{error}");
        assert!(CountedPurposes::including("").is_err());
    }
}
