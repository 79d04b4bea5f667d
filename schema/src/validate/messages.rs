//! Turns jsonschema's errors into [`FieldError`]s with plain sentences.
//!
//! The wording uses what the schemas say about a field: `x-unit` (the unit of a number),
//! `x-pattern-hint` (what a pattern means, in words), `description`, and the `properties` a
//! schema object declares.

use jsonschema::error::{TypeKind, ValidationErrorKind};
use jsonschema::{JsonType, ValidationError};
use serde_json::Value;

use super::FieldError;
use crate::pointer::{field_name, join};
use crate::schemas::{SchemaDocument, keyword_parent, resolve};

/// The sentences for one jsonschema error: usually one, one per key for unknown keys.
pub(super) fn field_errors(error: &ValidationError<'_>) -> Vec<FieldError> {
    let at = error.instance_path().as_str();
    describe(error, at, field_name(at))
}

/// The sentences for `error`, reported at `at` and naming the field `field`.
fn describe(error: &ValidationError<'_>, at: &str, field: String) -> Vec<FieldError> {
    let schema = error.absolute_keyword_location().and_then(|uri| keyword_parent(uri.as_str()));
    let one = |message: String| vec![FieldError::new(at, message)];
    let instance = error.instance().as_ref();
    match error.kind() {
        ValidationErrorKind::Required { property } => {
            let property = property.as_str().unwrap_or_default();
            // A `required` inside `if`/`then` has no `properties` beside it: look the field up
            // from the root of its document instead.
            let about = schema
                .and_then(|(doc, object)| {
                    property_schema(doc, object, property, 0)
                        .or_else(|| property_schema(doc, &doc.document, property, 0))
                })
                .and_then(|p| p["description"].as_str())
                .map(|d| format!(" {d}"))
                .unwrap_or_default();
            vec![FieldError::new(
                join(at, property),
                format!("{property} is required but missing.{about}"),
            )]
        }
        ValidationErrorKind::AdditionalProperties { unexpected }
        | ValidationErrorKind::UnevaluatedProperties { unexpected } => {
            let known = schema.map(|(doc, object)| known_fields(doc, object)).unwrap_or_default();
            unexpected
                .iter()
                .map(|key| FieldError::new(join(at, key), unknown_field(key, &field, &known)))
                .collect()
        }
        ValidationErrorKind::PropertyNames { error: inner } => {
            let key = inner.instance().as_str().unwrap_or_default();
            describe(inner, &join(at, key), "the key".to_owned())
        }
        ValidationErrorKind::Minimum { limit } => one(format!(
            "{field} is {}, below the minimum of {}.",
            quantity(instance, schema),
            quantity(limit, schema)
        )),
        ValidationErrorKind::ExclusiveMinimum { limit } => one(format!(
            "{field} is {}; it must be more than {}.",
            quantity(instance, schema),
            quantity(limit, schema)
        )),
        ValidationErrorKind::Maximum { limit } => one(format!(
            "{field} is {}, above the maximum of {}.",
            quantity(instance, schema),
            quantity(limit, schema)
        )),
        ValidationErrorKind::ExclusiveMaximum { limit } => one(format!(
            "{field} is {}; it must be less than {}.",
            quantity(instance, schema),
            quantity(limit, schema)
        )),
        ValidationErrorKind::Enum { options } => one(format!(
            "{field} is {instance}; it must be one of {}.",
            list(options.as_array().into_iter().flatten())
        )),
        ValidationErrorKind::Constant { expected_value } => {
            one(format!("{field} must be {expected_value}, not {instance}."))
        }
        ValidationErrorKind::Type { kind } => one(format!(
            "{field} must be {}, not {}.",
            expected_types(kind),
            type_phrase(JsonType::from(instance))
        )),
        ValidationErrorKind::Pattern { pattern } => {
            let hint = schema
                .and_then(|(_, object)| object["x-pattern-hint"].as_str())
                .map_or_else(|| format!("must match the pattern {pattern}"), str::to_owned);
            one(format!("{field} {instance} {hint}."))
        }
        ValidationErrorKind::MinLength { limit: 1 } => one(format!("{field} must not be empty.")),
        ValidationErrorKind::MinLength { limit } => {
            one(format!("{field} must be at least {limit} characters long."))
        }
        ValidationErrorKind::MaxLength { limit } => one(format!(
            "{field} is {} characters long; at most {limit} are allowed.",
            instance.as_str().map_or(0, |s| s.chars().count())
        )),
        ValidationErrorKind::MinItems { limit } => one(format!(
            "{field} has {} items; it needs {}.",
            array_len(instance),
            item_bound("at least", schema, "maxItems", *limit)
        )),
        ValidationErrorKind::MaxItems { limit } => one(format!(
            "{field} has {} items; it takes {}.",
            array_len(instance),
            item_bound("at most", schema, "minItems", *limit)
        )),
        ValidationErrorKind::MinProperties { limit: 1 } => {
            one(format!("{field} must have at least one entry."))
        }
        ValidationErrorKind::UniqueItems => {
            one(format!("{field} lists the same item more than once."))
        }
        ValidationErrorKind::Format { format } => one(format!(
            "{field} {instance} is not {}.",
            match format.as_str() {
                "date-time" => "an RFC 3339 date-time such as \"2024-05-01T12:00:00Z\"",
                "uuid" => "a UUID such as \"67e55044-10b1-426f-9247-bb680e5fe0c8\"",
                other => other,
            }
        )),
        ValidationErrorKind::AnyOf { context } => any_of(at, &field, context),
        ValidationErrorKind::OneOfNotValid { context } => match allowed_values(context) {
            Some(values) => {
                one(format!("{field} is {instance}; it must be one of {}.", list(values)))
            }
            None => one(format!("{field}: {}", error.masked())),
        },
        ValidationErrorKind::FalseSchema => one(format!("{field} is not allowed here.")),
        // The schemas use no other keyword a caretaker can trip over; should one appear,
        // jsonschema's own wording is better than nothing.
        _ => one(format!("{field}: {}", error.masked())),
    }
}

/// `anyOf` here is always "this, or null": report the branch that got further.
fn any_of(at: &str, field: &str, branches: &[Vec<ValidationError<'static>>]) -> Vec<FieldError> {
    let is_type = |e: &ValidationError<'_>| matches!(e.kind(), ValidationErrorKind::Type { .. });
    let specific: Vec<_> = branches.iter().filter(|errors| !errors.iter().all(is_type)).collect();
    if let [errors] = specific.as_slice() {
        return errors.iter().flat_map(field_errors).collect();
    }
    let expected: Vec<String> = branches
        .iter()
        .flatten()
        .filter_map(|e| match e.kind() {
            ValidationErrorKind::Type { kind } => Some(expected_types(kind)),
            _ => None,
        })
        .collect();
    vec![FieldError::new(at, format!("{field} must be {}.", expected.join(" or ")))]
}

/// The values a `oneOf` of `{"const", "title"}` choices allows (the schemas' way of giving
/// each allowed value a title), or None when the branches are anything else.
fn allowed_values<'a>(branches: &'a [Vec<ValidationError<'static>>]) -> Option<Vec<&'a Value>> {
    branches
        .iter()
        .map(|errors| match errors.as_slice() {
            [only] => match only.kind() {
                ValidationErrorKind::Constant { expected_value } => Some(&**expected_value),
                _ => None,
            },
            _ => None,
        })
        .collect()
}

/// A number with the unit the schema gives it, e.g. `500 N`.
fn quantity(value: &Value, schema: Option<(&SchemaDocument, &Value)>) -> String {
    match schema.and_then(|(_, object)| object["x-unit"].as_str()) {
        Some(unit) => format!("{value} {unit}"),
        None => value.to_string(),
    }
}

fn unknown_field(key: &str, parent: &str, known: &[String]) -> String {
    let place = if parent == "the document" {
        "at the top level".to_owned()
    } else {
        format!("in {parent}")
    };
    if known.is_empty() {
        format!("{key} is not a known field {place}.")
    } else {
        format!("{key} is not a known field {place}; the known fields are {}.", known.join(", "))
    }
}

/// "exactly N" when the other bound equals this one (a pair, a vector), else "`otherwise` N".
fn item_bound(
    otherwise: &str,
    schema: Option<(&SchemaDocument, &Value)>,
    other_bound: &str,
    limit: u64,
) -> String {
    let other = schema.and_then(|(_, object)| object[other_bound].as_u64());
    let qualifier = if other == Some(limit) { "exactly" } else { otherwise };
    format!("{qualifier} {limit}")
}

fn array_len(value: &Value) -> usize {
    value.as_array().map_or(0, Vec::len)
}

fn list<'a>(values: impl IntoIterator<Item = &'a Value>) -> String {
    values.into_iter().map(Value::to_string).collect::<Vec<_>>().join(", ")
}

fn expected_types(kind: &TypeKind) -> String {
    match kind {
        TypeKind::Single(ty) => type_phrase(*ty).to_owned(),
        // "true or false or null" reads better than the set's own order, null first.
        TypeKind::Multiple(types) => {
            let (null, others): (Vec<JsonType>, Vec<JsonType>) =
                types.iter().partition(|ty| *ty == JsonType::Null);
            others.into_iter().chain(null).map(type_phrase).collect::<Vec<_>>().join(" or ")
        }
    }
}

fn type_phrase(ty: JsonType) -> &'static str {
    match ty {
        JsonType::Array => "a list",
        JsonType::Boolean => "true or false",
        JsonType::Integer => "a whole number",
        JsonType::Null => "null",
        JsonType::Number => "a number",
        JsonType::Object => "an object",
        JsonType::String => "text",
    }
}

/// How deep `$ref` chains are followed when looking up fields; the schemas nest two deep.
const MAX_REF_DEPTH: usize = 8;

/// The schema of `property` in the object schema `object`, following `$ref`s.
fn property_schema(
    doc: &'static SchemaDocument,
    object: &'static Value,
    property: &str,
    depth: usize,
) -> Option<&'static Value> {
    if let Some(found) = object["properties"].get(property) {
        return Some(found);
    }
    let (doc, target) = resolve(doc, object["$ref"].as_str()?)?;
    (depth < MAX_REF_DEPTH).then(|| property_schema(doc, target, property, depth + 1)).flatten()
}

/// The fields an object schema declares for input (read-only ones left out), following
/// `$ref`s.
fn known_fields(doc: &'static SchemaDocument, object: &'static Value) -> Vec<String> {
    let mut fields = Vec::new();
    let mut next = Some((doc, object));
    for _ in 0..MAX_REF_DEPTH {
        let Some((doc, object)) = next else { break };
        if let Some(properties) = object["properties"].as_object() {
            fields.extend(
                properties
                    .iter()
                    .filter(|(_, p)| p["readOnly"] != Value::Bool(true))
                    .map(|(name, _)| name.clone()),
            );
        }
        next = object["$ref"].as_str().and_then(|r| resolve(doc, r));
    }
    fields
}
