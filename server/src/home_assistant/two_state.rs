//! A two-state tag's state, as trials alone tell it: a light on or off, a drawer open or
//! closed. Never from a press: only a robot's success detector, or a person's verdict on a
//! trial, says what the world is like.

use serde_json::Value;

use crate::store::home_assistant::TrialVerdict;

/// Which pair of states a tag has, from its actions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TwoState {
    /// `on` and `off`: a light (switches and pull-chain lamps).
    Light,
    /// `open` and `close`: a drawer, a door.
    Opening,
}

impl TwoState {
    /// The pair a tag with these actions has, if any.
    pub fn of<'a>(actions: impl Iterator<Item = &'a str> + Clone) -> Option<Self> {
        let has = |wanted: &str| actions.clone().any(|action| action == wanted);
        if has("on") && has("off") {
            Some(Self::Light)
        } else if has("open") && has("close") {
            Some(Self::Opening)
        } else {
            None
        }
    }

    /// Home Assistant's binary-sensor class for it.
    pub fn device_class(self) -> &'static str {
        match self {
            Self::Light => "light",
            Self::Opening => "opening",
        }
    }

    /// Whether the action, done, leaves the tag on (open): `None` for other actions.
    fn after(self, action: &str) -> Option<bool> {
        match (self, action) {
            (Self::Light, "on") | (Self::Opening, "open") => Some(true),
            (Self::Light, "off") | (Self::Opening, "close") => Some(false),
            _ => None,
        }
    }

    /// What one trial says: on (open) or off (closed), or `None` when it says nothing.
    /// A trial a person called wrong says nothing; a light's detector that saw the light go
    /// on or off says so even when that was not what was asked (a pull-chain lamp toggles);
    /// otherwise a success (the robot's detector, or a person's yes) left the asked-for state.
    pub fn said_by(self, trial: &TrialVerdict) -> Option<bool> {
        if trial.confirmed == Some(false) {
            return None;
        }
        if self == Self::Light {
            let body: Value = serde_json::from_str(&trial.body).unwrap_or(Value::Null);
            match body["detector"]["saw"].as_str() {
                Some("turned_on") => return Some(true),
                Some("turned_off") => return Some(false),
                _ => {}
            }
        }
        let worked = trial.confirmed == Some(true) || trial.outcome == "success";
        if worked { self.after(&trial.action) } else { None }
    }

    /// The state the newest telling trial gives (`trials` newest first); `None`: unknown.
    pub fn told_by(self, trials: &[TrialVerdict]) -> Option<bool> {
        trials.iter().find_map(|trial| self.said_by(trial))
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    fn trial(
        action: &str,
        outcome: &str,
        confirmed: Option<bool>,
        saw: Option<&str>,
    ) -> TrialVerdict {
        let detector = saw.map_or(json!({}), |saw| json!({ "saw": saw }));
        TrialVerdict {
            action: action.into(),
            outcome: outcome.into(),
            confirmed,
            body: json!({ "detector": detector }).to_string(),
        }
    }

    #[test]
    fn pairs_come_from_the_actions() {
        assert_eq!(TwoState::of(["on", "off"].into_iter()), Some(TwoState::Light));
        assert_eq!(TwoState::of(["close", "open"].into_iter()), Some(TwoState::Opening));
        assert_eq!(TwoState::of(["on"].into_iter()), None);
        assert_eq!(TwoState::of(["drop"].into_iter()), None);
    }

    #[test]
    fn unknown_until_a_trial_tells() {
        assert_eq!(TwoState::Light.told_by(&[]), None);
        let failed = trial("off", "failure", None, Some("unchanged"));
        assert_eq!(TwoState::Light.told_by(&[failed]), None);
    }

    #[test]
    fn the_detector_says_what_the_light_did() {
        let asked_on_saw_off = trial("on", "failure", None, Some("turned_off"));
        assert_eq!(TwoState::Light.said_by(&asked_on_saw_off), Some(false));
        let done = trial("off", "success", None, Some("turned_off"));
        assert_eq!(TwoState::Light.said_by(&done), Some(false));
    }

    #[test]
    fn a_person_overrules_the_robot() {
        let wrongly_claimed = trial("open", "success", Some(false), None);
        let older = trial("close", "success", None, None);
        let trials = [wrongly_claimed, older];
        assert_eq!(TwoState::Opening.told_by(&trials), Some(false));
        let confirmed_failure = trial("open", "failure", Some(true), None);
        assert_eq!(TwoState::Opening.said_by(&confirmed_failure), Some(true));
    }
}
