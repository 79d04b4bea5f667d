//! Phase 4's decisions (paper §IV-B): "If there is only one possible action, EL-E performs it.
//! If there are two, EL-E asks the user to select between the two choices by pointing the laser
//! pointer either up or down". Then the behaviour the action names runs with its parameters.

use pps_schema::{BehaviorParams, Properties, StateChange, TagEntry};

use super::task_robot::TaskRobot;
use crate::behaviors::{
    BehaviorReport, DropGeometry, ForceRecorder, WantedLight, drop_object, operate_light_switch,
    pull_back, pull_lamp, push,
};
use crate::hal::{HalError, LookDirection, Operator, VerticalChoice};

/// Action names that mean "more": turning on, opening. Pointing up picks them.
const UP_WORDS: [&str; 4] = ["on", "open", "up", "raise"];

/// How the action was chosen.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ActionChoice {
    /// The entry has one action.
    Only(String),
    /// The person pointed up or down between two.
    Asked { choice: VerticalChoice, action: String },
}

impl ActionChoice {
    pub fn action(&self) -> &str {
        match self {
            Self::Only(action) | Self::Asked { action, .. } => action,
        }
    }
}

/// The two actions as (up, down): the one that turns on or opens is up; otherwise the first
/// by name.
fn up_and_down(entry: &TagEntry) -> Option<(&str, &str)> {
    let mut names = entry.actions.keys().map(String::as_str);
    let (a, b) = (names.next()?, names.next()?);
    Some(if UP_WORDS.contains(&b) && !UP_WORDS.contains(&a) { (b, a) } else { (a, b) })
}

/// Which way the person points to choose `action` among the entry's two (the operator's side of
/// the same convention); `None` when the entry does not have two actions or not that one.
pub fn vertical_choice_for(entry: &TagEntry, action: &str) -> Option<VerticalChoice> {
    if entry.actions.len() != 2 {
        return None;
    }
    let (up, down) = up_and_down(entry)?;
    if action == up {
        Some(VerticalChoice::Up)
    } else if action == down {
        Some(VerticalChoice::Down)
    } else {
        None
    }
}

/// The action to perform: the only one, or the person's choice between two; `None` when the
/// entry offers none or more than two (the paper's interface chooses between two).
pub fn choose_action(
    entry: &TagEntry,
    operator: &dyn Operator,
) -> Result<Option<ActionChoice>, HalError> {
    match entry.actions.len() {
        1 => Ok(entry.actions.keys().next().cloned().map(ActionChoice::Only)),
        2 => {
            let (up, down) = up_and_down(entry).expect("two actions");
            let choice = operator.choose_action()?;
            let action = match choice {
                VerticalChoice::Up => up,
                VerticalChoice::Down => down,
            };
            Ok(Some(ActionChoice::Asked { choice, action: action.to_owned() }))
        }
        _ => Ok(None),
    }
}

/// Where the entry says to look for the change.
fn look(properties: &Properties) -> LookDirection {
    match properties.direction {
        Some(pps_schema::LookDirection::Up) => LookDirection::Up,
        _ => LookDirection::Forward,
    }
}

/// Runs the behaviour with its (merged) parameters.
pub(crate) fn run_behavior(
    robot: &impl TaskRobot,
    params: &BehaviorParams,
    properties: &Properties,
    action: &str,
    drop: &DropGeometry,
    forces: ForceRecorder<'_>,
) -> Result<BehaviorReport, HalError> {
    let wanted = WantedLight::for_action(action);
    match params {
        BehaviorParams::LightSwitch(p) => {
            operate_light_switch(robot, p, look(properties), wanted, forces)
        }
        BehaviorParams::PullBack(p) => pull_back(robot, p, forces),
        BehaviorParams::Push(p) => {
            let change = properties.change.unwrap_or(StateChange::Location);
            push(robot, p, change, look(properties), wanted, forces)
        }
        BehaviorParams::PullLamp(p) => pull_lamp(robot, p, look(properties), wanted, forces),
        BehaviorParams::Drop(p) => drop_object(robot, p, drop, forces),
    }
}
