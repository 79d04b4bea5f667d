//! Behaviour specifications: which robot behaviour performs an action, and its parameters.
//!
//! One module per behaviour, each mirroring `schemas/<behaviour>.schema.json`; the serde
//! defaults here equal the schema's `default`s (a test holds them together).

mod drop;
mod light_switch;
mod pull_back;
mod pull_lamp;
mod push;

use std::collections::BTreeMap;
use std::fmt;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

pub use drop::DropParams;
pub use light_switch::{LightSwitchParams, SweepDirection, SwitchMotion};
pub use pull_back::PullBackParams;
pub use pull_lamp::PullLampParams;
pub use push::PushParams;

/// The robot behaviours of the paper (§IV-B.2), as named in entries and robot capabilities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BehaviorKind {
    LightSwitch,
    PullBack,
    Push,
    PullLamp,
    Drop,
}

impl BehaviorKind {
    pub const ALL: [BehaviorKind; 5] =
        [Self::LightSwitch, Self::PullBack, Self::Push, Self::PullLamp, Self::Drop];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::LightSwitch => "light_switch",
            Self::PullBack => "pull_back",
            Self::Push => "push",
            Self::PullLamp => "pull_lamp",
            Self::Drop => "drop",
        }
    }

    /// The name of this behaviour's schema, for [`crate::schema_document`].
    pub fn schema_name(self) -> &'static str {
        self.as_str()
    }
}

impl fmt::Display for BehaviorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A name that is not one of [`BehaviorKind::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{0:?} is not a behaviour; the behaviours are light_switch, pull_back, push, pull_lamp and drop"
)]
pub struct UnknownBehavior(pub String);

impl std::str::FromStr for BehaviorKind {
    type Err = UnknownBehavior;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|kind| kind.as_str() == s)
            .ok_or_else(|| UnknownBehavior(s.to_owned()))
    }
}

/// The parameters of one behaviour, tagged by its `behavior` field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "behavior", rename_all = "snake_case")]
pub enum BehaviorParams {
    LightSwitch(LightSwitchParams),
    PullBack(PullBackParams),
    Push(PushParams),
    PullLamp(PullLampParams),
    Drop(DropParams),
}

impl BehaviorParams {
    pub fn kind(&self) -> BehaviorKind {
        match self {
            Self::LightSwitch(_) => BehaviorKind::LightSwitch,
            Self::PullBack(_) => BehaviorKind::PullBack,
            Self::Push(_) => BehaviorKind::Push,
            Self::PullLamp(_) => BehaviorKind::PullLamp,
            Self::Drop(_) => BehaviorKind::Drop,
        }
    }

    /// The largest force, in newtons, these parameters let the behaviour command, for checking
    /// against a robot's `limits.max_force`; `None` when it commands no force (drop).
    pub fn peak_force(&self) -> Option<f64> {
        match self {
            Self::LightSwitch(p) => Some(p.peak_force()),
            Self::PullBack(p) => Some(p.grasp_force.max(p.stop_force)),
            Self::Push(p) => Some(p.contact_force.max(p.stop_force)),
            Self::PullLamp(p) => Some(p.grip_force.max(p.max_pull_force)),
            Self::Drop(_) => None,
        }
    }
}

/// Parameters overridden for one robot class or robot: any subset of the behaviour's own
/// parameters, as JSON, so that the parameter list is written once (in the parameter structs).
pub type ParamOverride = Map<String, Value>;

/// One entry of `behaviors`: a behaviour, its parameters and per-robot overrides.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BehaviorSpec {
    #[serde(flatten)]
    pub params: BehaviorParams,
    /// Robot class or robot id → the parameters that differ for it.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub robots: BTreeMap<String, ParamOverride>,
}

impl BehaviorSpec {
    pub fn kind(&self) -> BehaviorKind {
        self.params.kind()
    }

    /// The parameters for `robot` of `class`: the base, then the class's override, then the
    /// robot's own (later wins, as in the registry's effective entry).
    ///
    /// Fails only when an override holds a value of the wrong type, which a validated entry
    /// never does.
    pub fn params_for(
        &self,
        class: Option<&str>,
        robot: &str,
    ) -> Result<BehaviorParams, serde_json::Error> {
        let overrides: Vec<&ParamOverride> =
            class.into_iter().chain([robot]).filter_map(|key| self.robots.get(key)).collect();
        if overrides.is_empty() {
            return Ok(self.params.clone());
        }
        let mut merged = serde_json::to_value(&self.params)?;
        if let Value::Object(fields) = &mut merged {
            for (name, value) in overrides.into_iter().flatten() {
                fields.insert(name.clone(), value.clone());
            }
        }
        serde_json::from_value(merged)
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    #[test]
    fn names_round_trip() {
        for kind in BehaviorKind::ALL {
            assert_eq!(kind.as_str().parse::<BehaviorKind>(), Ok(kind));
            assert_eq!(serde_json::to_value(kind).unwrap(), json!(kind.as_str()));
        }
        assert!("open_door".parse::<BehaviorKind>().is_err());
    }

    #[test]
    fn names_match_the_schema_enum() {
        let tag = crate::schemas::schema_document("tag").unwrap();
        let names: Vec<&str> = BehaviorKind::ALL.iter().map(|k| k.as_str()).collect();
        let choices = tag["$defs"]["behavior_name"]["oneOf"].as_array().unwrap();
        let consts: Vec<&Value> = choices.iter().map(|choice| &choice["const"]).collect();
        assert_eq!(json!(consts), json!(names));
        assert!(
            choices.iter().all(|choice| choice["title"].is_string()),
            "every behaviour has a title"
        );
        for kind in BehaviorKind::ALL {
            assert!(crate::schemas::schema_document(kind.schema_name()).is_some());
        }
    }

    #[test]
    fn defaults_fill_what_the_entry_leaves_out() {
        let spec: BehaviorSpec =
            serde_json::from_value(json!({"behavior": "pull_lamp", "grip_force": 4.0})).unwrap();
        let BehaviorParams::PullLamp(p) = &spec.params else { panic!("{spec:?}") };
        assert_eq!(p.grip_force, 4.0);
        assert_eq!(p.max_pull_force, 10.0);
        assert_eq!(p.max_pull_distance, 0.07);
        assert_eq!(p.alignment_backoff, 0.08);
    }

    #[test]
    fn robot_override_wins_over_class_override_over_base() {
        let spec: BehaviorSpec = serde_json::from_value(json!({
            "behavior": "light_switch", "force_threshold": 3.0, "gripper_deg": 20,
            "robots": {
                "el-e": {"gripper_deg": 5, "force_threshold": 4.0},
                "el-e-2": {"force_threshold": 2.5}
            }
        }))
        .unwrap();
        let params = |class, robot| match spec.params_for(class, robot).unwrap() {
            BehaviorParams::LightSwitch(p) => (p.gripper_deg, p.force_threshold),
            other => panic!("{other:?}"),
        };
        assert_eq!(params(None, "pr2-1"), (20.0, 3.0));
        assert_eq!(params(Some("el-e"), "el-e-1"), (5.0, 4.0));
        assert_eq!(params(Some("el-e"), "el-e-2"), (5.0, 2.5));
        assert_eq!(params(None, "el-e-2"), (20.0, 2.5));
    }

    #[test]
    fn peak_force_is_the_largest_commanded_force() {
        let spec = |v| serde_json::from_value::<BehaviorSpec>(v).unwrap().params;
        let press = spec(json!({"behavior": "light_switch", "force_threshold": 3.0}));
        let flip = spec(json!({"behavior": "light_switch", "motion": "flip", "direction": "up"}));
        let pull = spec(json!({"behavior": "pull_back", "pull_distance": 0.3, "stop_force": 14}));
        let drop = spec(json!({"behavior": "drop"}));
        assert_eq!(press.peak_force(), Some(3.0));
        assert_eq!(flip.peak_force(), Some(12.0));
        assert_eq!(pull.peak_force(), Some(14.0));
        assert_eq!(drop.peak_force(), None);
    }
}
