//! Accepting a tag entry from a client: read-only fields dropped, the EPC reconciled with the
//! URL, and every schema and cross-field error reported at once.

use pps_schema::{Epc, FieldError, Validator};
use serde_json::Value;

use crate::error::ApiError;

/// Turns a submitted entry into the entry the registry stores, or lists everything wrong.
///
/// `expected` is the EPC from the URL; the body may omit `epc` or spell it in any case.
pub fn accept(expected: Option<&Epc>, mut body: Value) -> Result<(Epc, Value), ApiError> {
    pps_schema::strip_read_only(&mut body);
    let Some(object) = body.as_object_mut() else {
        return Err(ApiError::invalid_at("", "a tag entry is a JSON object"));
    };
    let mut errors = Vec::new();
    let epc = match (object.get("epc"), expected) {
        (None, Some(expected)) => Some(expected.clone()),
        (Some(Value::String(text)), _) => match Epc::parse(text) {
            Ok(epc) if expected.is_some_and(|expected| *expected != epc) => {
                errors.push(FieldError {
                    pointer: "/epc".into(),
                    message: format!(
                        "the entry's epc {epc} differs from the EPC in the URL {}; they must be the same",
                        expected.map(Epc::as_hex).unwrap_or_default()
                    ),
                });
                None
            }
            Ok(epc) => Some(epc),
            // The validator reports a malformed epc itself.
            Err(_) => None,
        },
        _ => None,
    };
    if let Some(epc) = &epc {
        object.insert("epc".into(), epc.as_hex().into());
    }
    if let Err(invalid) = Validator::get().validate_tag(&body) {
        errors.extend(invalid);
    }
    match epc {
        Some(epc) if errors.is_empty() => Ok((epc, body)),
        _ => Err(ApiError::Invalid(errors)),
    }
}
