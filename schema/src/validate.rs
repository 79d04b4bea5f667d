//! Validation of tag entries, trials and robots against the contract: every JSON Schema error
//! and every cross-field rule, together, in sentences a caretaker can act on.
//!
//! The schemas are compiled once per process ([`Validator::get`]); validating never touches
//! the network or the file system.

mod messages;

mod rules;

use std::fmt;
use std::sync::LazyLock;

use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::schemas::{documents, schema_document};

/// One problem with a document.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "field_error"))]
pub struct FieldError {
    /// RFC 6901 JSON pointer into the document to the field the problem is about (`""` for the
    /// whole document). For a missing field it points where the field belongs.
    pub pointer: String,
    /// A sentence naming the field, and the bound and unit where there is one.
    #[cfg_attr(feature = "schemars", schemars(length(min = 1)))]
    pub message: String,
}

impl FieldError {
    pub fn new(pointer: impl Into<String>, message: impl Into<String>) -> Self {
        Self { pointer: pointer.into(), message: message.into() }
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let pointer = if self.pointer.is_empty() { "(document)" } else { &self.pointer };
        write!(f, "{pointer}: {}", self.message)
    }
}

/// Every problem found in one document, ordered by pointer. Serializes as a JSON array of
/// [`FieldError`]s.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ValidationErrors(Vec<FieldError>);

impl ValidationErrors {
    pub fn errors(&self) -> &[FieldError] {
        &self.0
    }

    pub fn into_vec(self) -> Vec<FieldError> {
        self.0
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The problems reported at exactly `pointer`.
    pub fn at<'a>(&'a self, pointer: &'a str) -> impl Iterator<Item = &'a FieldError> {
        self.0.iter().filter(move |e| e.pointer == pointer)
    }
}

impl fmt::Display for ValidationErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0.len() {
            1 => write!(f, "1 problem: ")?,
            n => write!(f, "{n} problems: ")?,
        }
        for (i, error) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str("; ")?;
            }
            write!(f, "{error}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ValidationErrors {}

impl IntoIterator for ValidationErrors {
    type Item = FieldError;
    type IntoIter = std::vec::IntoIter<FieldError>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.into_iter()
    }
}

impl<'a> IntoIterator for &'a ValidationErrors {
    type Item = &'a FieldError;
    type IntoIter = std::slice::Iter<'a, FieldError>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}

/// The compiled schemas. Compiling takes milliseconds, so it happens once: use
/// [`Validator::get`] (or the free functions [`validate_tag`], [`validate_trial`],
/// [`validate_robot`]).
pub struct Validator {
    tag: jsonschema::Validator,
    trial: jsonschema::Validator,
    robot: jsonschema::Validator,
}

impl fmt::Debug for Validator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Validator").finish_non_exhaustive()
    }
}

static VALIDATOR: LazyLock<Validator> = LazyLock::new(Validator::compile);

impl Validator {
    /// The validator of this process, compiled on first use.
    pub fn get() -> &'static Validator {
        &VALIDATOR
    }

    fn compile() -> Self {
        // Every schema is a resource of one registry, so `$ref`s between the files resolve
        // from memory; nothing is fetched.
        let registry = jsonschema::Registry::new()
            .extend(documents().iter().map(|doc| (doc.id.as_str(), &doc.document)))
            .and_then(|builder| builder.prepare())
            .unwrap_or_else(|e| panic!("the embedded schemas do not form a registry: {e}"));
        let build = |name: &str| {
            let schema = schema_document(name).expect("a schema of this crate");
            jsonschema::draft202012::options()
                .should_validate_formats(true)
                .with_registry(&registry)
                .build(schema)
                .unwrap_or_else(|e| panic!("schemas/{name}.schema.json does not compile: {e}"))
        };
        Self { tag: build("tag"), trial: build("trial"), robot: build("robot") }
    }

    /// Checks a tag entry (as PUT: read-only fields are allowed and ignored).
    pub fn validate_tag(&self, entry: &Value) -> Result<(), ValidationErrors> {
        check(&self.tag, entry, rules::tag)
    }

    /// Checks a trial.
    pub fn validate_trial(&self, trial: &Value) -> Result<(), ValidationErrors> {
        check(&self.trial, trial, rules::trial)
    }

    /// Checks a robot.
    pub fn validate_robot(&self, robot: &Value) -> Result<(), ValidationErrors> {
        check(&self.robot, robot, rules::robot)
    }
}

/// Checks a tag entry with the process's [`Validator`].
pub fn validate_tag(entry: &Value) -> Result<(), ValidationErrors> {
    Validator::get().validate_tag(entry)
}

/// Checks a trial with the process's [`Validator`].
pub fn validate_trial(trial: &Value) -> Result<(), ValidationErrors> {
    Validator::get().validate_trial(trial)
}

/// Checks a robot with the process's [`Validator`].
pub fn validate_robot(robot: &Value) -> Result<(), ValidationErrors> {
    Validator::get().validate_robot(robot)
}

fn check(
    schema: &jsonschema::Validator,
    document: &Value,
    rules: fn(&Value) -> Vec<FieldError>,
) -> Result<(), ValidationErrors> {
    let mut errors: Vec<FieldError> =
        schema.iter_errors(document).flat_map(|error| messages::field_errors(&error)).collect();
    // A field the schema already rejected gets no second, cross-field complaint.
    let cross_field: Vec<FieldError> = rules(document)
        .into_iter()
        .filter(|rule| errors.iter().all(|e| e.pointer != rule.pointer))
        .collect();
    errors.extend(cross_field);
    errors.sort_by(|a, b| a.pointer.cmp(&b.pointer));
    errors.dedup();
    if errors.is_empty() { Ok(()) } else { Err(ValidationErrors(errors)) }
}
