//! Cross-field rules: what one JSON Schema cannot say because it relates two fields, or needs
//! a parser of this crate.
//!
//! Each rule reads the raw document and skips what is missing or mistyped: the schema reports
//! that, and a rule must never report the same field twice.

use serde_json::Value;
use time::OffsetDateTime;
use time::format_description::well_known::Rfc3339;

use super::FieldError;
use crate::epc::Epc;
use crate::pointer::join;
use crate::robot_id::RobotId;

pub(super) fn tag(entry: &Value) -> Vec<FieldError> {
    let mut errors = Vec::new();
    let own_epc = parsed_epc(entry, "/epc", &mut errors);
    actions_resolve(entry, &mut errors);
    links_point_elsewhere(entry, own_epc.as_ref(), &mut errors);
    color_ranges_ordered(entry, &mut errors);
    errors
}

pub(super) fn trial(trial: &Value) -> Vec<FieldError> {
    let mut errors = Vec::new();
    parsed_epc(trial, "/epc", &mut errors);
    parsed_robot_id(trial, "/robot", &mut errors);
    finished_after_started(trial, &mut errors);
    errors
}

pub(super) fn robot(robot: &Value) -> Vec<FieldError> {
    let mut errors = Vec::new();
    parsed_robot_id(robot, "/id", &mut errors);
    parsed_robot_id(robot, "/class", &mut errors);
    errors
}

/// The EPC at `pointer`, when it is text; a complaint when [`Epc::parse`] refuses it.
fn parsed_epc(document: &Value, pointer: &str, errors: &mut Vec<FieldError>) -> Option<Epc> {
    let text = document.pointer(pointer)?.as_str()?;
    Epc::parse(text)
        .map_err(|e| errors.push(FieldError::new(pointer, format!("epc {text:?}: {e}."))))
        .ok()
}

fn parsed_robot_id(document: &Value, pointer: &str, errors: &mut Vec<FieldError>) {
    let Some(text) = document.pointer(pointer).and_then(Value::as_str) else {
        return;
    };
    if let Err(e) = RobotId::parse(text) {
        let field = &pointer[1..];
        errors.push(FieldError::new(pointer, format!("{field} {text:?}: {e}.")));
    }
}

/// Every action names a key of `behaviors`.
fn actions_resolve(entry: &Value, errors: &mut Vec<FieldError>) {
    let (Some(actions), Some(behaviors)) =
        (entry["actions"].as_object(), entry["behaviors"].as_object())
    else {
        return;
    };
    for (action, key) in actions {
        let Some(key) = key.as_str() else { continue };
        if behaviors.contains_key(key) {
            continue;
        }
        let existing = if behaviors.is_empty() {
            "no behaviours are defined yet".to_owned()
        } else {
            let keys: Vec<&str> = behaviors.keys().map(String::as_str).collect();
            format!("the behaviours are {}", keys.join(", "))
        };
        errors.push(FieldError::new(
            join("/actions", action),
            format!(
                "action {action:?} runs behaviour {key:?}, which is not in behaviors; \
                 {existing}."
            ),
        ));
    }
}

/// A link relates this tag to another one, never to itself.
fn links_point_elsewhere(entry: &Value, own: Option<&Epc>, errors: &mut Vec<FieldError>) {
    let (Some(own), Some(links)) = (own, entry["links"].as_array()) else {
        return;
    };
    for (i, link) in links.iter().enumerate() {
        let target = link["target"].as_str().and_then(|t| Epc::parse(t).ok());
        if target.as_ref() == Some(own) {
            errors.push(FieldError::new(
                format!("/links/{i}/target"),
                format!(
                    "target is this entry's own EPC {own}; a link must name another tag's EPC."
                ),
            ));
        }
    }
}

/// Saturation and value are plain ranges (only hue wraps around), so min must not exceed max.
fn color_ranges_ordered(entry: &Value, errors: &mut Vec<FieldError>) {
    let Some(robots) = entry.pointer("/properties/robots").and_then(Value::as_object) else {
        return;
    };
    for (robot, properties) in robots {
        let at = join(&join("/properties/robots", robot), "color_segmentation");
        for channel in ["saturation", "value"] {
            let range = &properties["color_segmentation"][channel];
            let (Some(min), Some(max)) = (range[0].as_f64(), range[1].as_f64()) else {
                continue;
            };
            if min > max {
                errors.push(FieldError::new(
                    join(&at, channel),
                    format!(
                        "{channel} [{min}, {max}] has its minimum above its maximum; \
                         write [min, max], e.g. [{max}, {min}] (only hue_deg wraps around)."
                    ),
                ));
            }
        }
    }
}

/// A trial cannot finish before it starts.
fn finished_after_started(trial: &Value, errors: &mut Vec<FieldError>) {
    let time =
        |field: &str| trial[field].as_str().and_then(|t| OffsetDateTime::parse(t, &Rfc3339).ok());
    if let (Some(started), Some(finished)) = (time("started_at"), time("finished_at"))
        && finished < started
    {
        errors.push(FieldError::new(
            "/finished_at",
            format!(
                "finished_at ({}) is {} s before started_at ({}); a trial cannot finish \
                 before it starts.",
                trial["finished_at"].as_str().unwrap_or_default(),
                (started - finished).as_seconds_f64(),
                trial["started_at"].as_str().unwrap_or_default(),
            ),
        ));
    }
}
