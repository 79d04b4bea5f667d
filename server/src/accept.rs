//! Accepting a document from a client (a tag entry, a robot, a trial): read-only fields
//! dropped, the id reconciled with the URL's, and every schema and id problem reported at once.
//!
//! The steps are the same for every kind; [`Document`] says how each kind spells and compares
//! its id and how its problems have always been worded.

use std::fmt;
use std::str::FromStr;

use pps_schema::{
    Epc, FieldError, READ_ONLY_ROBOT_FIELDS, READ_ONLY_TAG_FIELDS, READ_ONLY_TRIAL_FIELDS, Robot,
    RobotId, TagEntry, Trial, ValidationErrors, strip_fields,
};
use serde_json::Value;
use uuid::Uuid;

use crate::error::ApiError;

/// A kind of document clients submit, named by an id in the URL and in the body.
pub trait Document {
    /// What the URL names the document by.
    type Id: Clone + fmt::Display;
    /// The body's field holding the id.
    const ID_FIELD: &'static str = "id";
    /// Top-level fields the registry writes; dropped, so that GET, edit, PUT round-trips.
    const READ_ONLY: &'static [&'static str];
    /// The answer to a body that is not a JSON object; `None` leaves it to the schema.
    const NOT_AN_OBJECT: Option<&'static str> = None;
    /// Whether a differing id is listed before the schema's problems rather than after them,
    /// as clients have always been shown.
    const ID_PROBLEM_FIRST: bool = false;
    /// The document's JSON Schema check.
    const VALIDATE: fn(&Value) -> Result<(), ValidationErrors>;

    /// The body's id as spelled, `text`, against the URL's.
    fn reconcile(text: &str, url: Option<&Self::Id>) -> BodyId<Self::Id>;

    /// The id as written into a body that names none.
    fn to_json(id: &Self::Id) -> Value {
        id.to_string().into()
    }
}

/// What the body's id says next to the URL's.
#[derive(Debug)]
pub enum BodyId<Id> {
    /// The URL's document (or, without a URL id, this one); the body keeps its spelling.
    Same(Id),
    /// The same, to be stored in the id's canonical spelling.
    Respelled(Id),
    /// Another document: the problem, worded for the client.
    Differs(String),
    /// Not an id at all; the schema says why.
    Unreadable,
}

/// Turns a submitted document into the one the registry stores, with its id, or lists
/// everything wrong with it. `url` is the id from the URL, when there is one.
pub fn accept<D: Document>(
    url: Option<&D::Id>,
    mut body: Value,
) -> Result<(D::Id, Value), ApiError> {
    strip_fields(&mut body, D::READ_ONLY);
    let (id, id_problem) = match body.as_object_mut() {
        Some(object) => {
            let reconciled = match object.get(D::ID_FIELD) {
                None => url.cloned().map(BodyId::Respelled),
                Some(Value::String(text)) => Some(D::reconcile(text, url)),
                // The schema reports an id of the wrong type.
                Some(_) => None,
            };
            match reconciled {
                Some(BodyId::Respelled(id)) => {
                    object.insert(D::ID_FIELD.into(), D::to_json(&id));
                    (Some(id), None)
                }
                Some(BodyId::Same(id)) => (Some(id), None),
                Some(BodyId::Differs(message)) => (
                    None,
                    Some(FieldError::new(pps_schema::pointer::join("", D::ID_FIELD), message)),
                ),
                Some(BodyId::Unreadable) | None => (None, None),
            }
        }
        None => match D::NOT_AN_OBJECT {
            Some(message) => return Err(ApiError::invalid_at("", message)),
            None => (None, None),
        },
    };
    let schema_problems = (D::VALIDATE)(&body).err().map(ValidationErrors::into_vec);
    let (before, after) = if D::ID_PROBLEM_FIRST { (id_problem, None) } else { (None, id_problem) };
    let errors: Vec<FieldError> =
        before.into_iter().chain(schema_problems.into_iter().flatten()).chain(after).collect();
    match id {
        Some(id) if errors.is_empty() => Ok((id, body)),
        _ => Err(ApiError::Invalid(errors)),
    }
}

/// A tag entry: the body may omit `epc` or spell it in any accepted form; it is stored in hex.
impl Document for TagEntry {
    type Id = Epc;
    const ID_FIELD: &'static str = "epc";
    const READ_ONLY: &'static [&'static str] = READ_ONLY_TAG_FIELDS;
    const NOT_AN_OBJECT: Option<&'static str> = Some("a tag entry is a JSON object");
    const ID_PROBLEM_FIRST: bool = true;
    const VALIDATE: fn(&Value) -> Result<(), ValidationErrors> = pps_schema::validate_tag;

    fn reconcile(text: &str, url: Option<&Epc>) -> BodyId<Epc> {
        match Epc::parse(text) {
            Ok(epc) if url.is_some_and(|url| *url != epc) => BodyId::Differs(format!(
                "the entry's epc {epc} differs from the EPC in the URL {}; they must be the same",
                url.map(Epc::as_hex).unwrap_or_default()
            )),
            Ok(epc) => BodyId::Respelled(epc),
            Err(_) => BodyId::Unreadable,
        }
    }

    fn to_json(epc: &Epc) -> Value {
        epc.as_hex().into()
    }
}

/// A robot: its id is compared byte for byte, as robot ids always are.
impl Document for Robot {
    type Id = RobotId;
    const READ_ONLY: &'static [&'static str] = READ_ONLY_ROBOT_FIELDS;
    const VALIDATE: fn(&Value) -> Result<(), ValidationErrors> = pps_schema::validate_robot;

    fn reconcile(text: &str, url: Option<&RobotId>) -> BodyId<RobotId> {
        as_spelled(
            text,
            url,
            |url| text == url.as_str(),
            |url| {
                format!(
                    "the robot's id differs from the id in the URL {url}; they must be the same"
                )
            },
        )
    }
}

/// A trial: its UUID may be spelled in either case, and is kept as the robot spelled it (a
/// retry must match the stored body exactly).
impl Document for Trial {
    type Id = Uuid;
    const READ_ONLY: &'static [&'static str] = READ_ONLY_TRIAL_FIELDS;
    const VALIDATE: fn(&Value) -> Result<(), ValidationErrors> = pps_schema::validate_trial;

    fn reconcile(text: &str, url: Option<&Uuid>) -> BodyId<Uuid> {
        let names = |url: &Uuid| text.eq_ignore_ascii_case(&url.hyphenated().to_string());
        as_spelled(text, url, names, |url| {
            format!("the trial's id differs from the id in the URL {url}")
        })
    }
}

/// Reconciles an id the body keeps as spelled: the URL's document when the body `names` it,
/// else the problem as `differs` words it.
fn as_spelled<Id: Clone + FromStr>(
    text: &str,
    url: Option<&Id>,
    names: impl FnOnce(&Id) -> bool,
    differs: impl FnOnce(&Id) -> String,
) -> BodyId<Id> {
    match url {
        Some(url) if names(url) => BodyId::Same(url.clone()),
        Some(url) => BodyId::Differs(differs(url)),
        None => text.parse().map_or(BodyId::Unreadable, BodyId::Same),
    }
}
