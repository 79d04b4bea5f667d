//! The PPS-tag contract shared by the registry and the robots: the JSON Schemas in
//! `schemas/`, the serde types that match them, the validator, and the [`Epc`] key.
//!
//! This crate depends on neither the server nor the robot client, and does no I/O: the
//! schemas are compiled into it.

mod behavior;
mod decline;
mod effective;
mod entry;
mod epc;
mod link;
pub mod pointer;
mod read_only;
mod robot;
mod robot_id;
mod schemas;
mod task_state;
mod trial;
mod validate;

pub use behavior::{
    BehaviorKind, BehaviorParams, BehaviorSpec, DropParams, LightSwitchParams, ParamOverride,
    PullBackParams, PullLampParams, PushParams, SweepDirection, SwitchMotion, UnknownBehavior,
};
pub use decline::{MAX_DECLINE_REASON_CHARS, decline_reason};
pub use effective::{EffectiveEntry, Provenance, ProvenanceError, UnavailableAction};
pub use entry::{
    ColorSegmentation, HOUSEHOLD_COLOR, LEARNED_COLOR, LearnedColor, Location, LookDirection,
    PpsTagMaterial, Properties, RobotProperties, StateChange, TagEntry, TagSize,
};
pub use epc::{Epc, EpcError};
pub use link::{Link, LinkRel};
pub use read_only::{
    READ_ONLY_ROBOT_FIELDS, READ_ONLY_TAG_FIELDS, READ_ONLY_TRIAL_FIELDS, strip_fields,
    strip_read_only,
};
pub use robot::{Robot, RobotLimits};
pub use robot_id::{RobotId, RobotIdError};
pub use schemas::{SCHEMA_BASE_URI, SCHEMA_NAMES, schema_document};
pub use task_state::{TaskState, TaskStateError};
pub use trial::{
    Finger, ForceSample, MAX_FORCE_SAMPLES, Outcome, Purpose, StartPose, TagColor, Trial,
};
pub use validate::{
    FieldError, ValidationErrors, Validator, validate_robot, validate_tag, validate_trial,
};
