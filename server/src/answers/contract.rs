//! Parts of answers whose shape the contract (`pps-schema`'s JSON Schemas) defines: their
//! schema is a `$ref` to the contract's own, never a restatement of it.

use std::borrow::Cow;

use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};

/// Where the components live in the OpenAPI document.
pub const SCHEMAS: &str = "#/components/schemas/";

macro_rules! contract_ref {
    ($(#[$doc:meta])* $name:ident => $path:literal) => {
        $(#[$doc])*
        #[derive(Debug)]
        pub struct $name;

        impl JsonSchema for $name {
            fn inline_schema() -> bool {
                true
            }

            fn schema_name() -> Cow<'static, str> {
                $path.into()
            }

            fn json_schema(_: &mut SchemaGenerator) -> Schema {
                json_schema!({ "$ref": concat!("#/components/schemas/", $path) })
            }
        }
    };
}

contract_ref!(
    /// A tag entry (`tag.schema.json`).
    Tag => "tag"
);
contract_ref!(
    /// A trial as a robot submits it (`trial.schema.json`).
    Trial => "trial"
);
contract_ref!(
    /// A robot as an admin registers it (`robot.schema.json`).
    Robot => "robot"
);
contract_ref!(
    /// An EPC in the canonical upper-case hex the registry returns.
    Epc => "tag/$defs/epc"
);
contract_ref!(
    /// A robot's id (or a robot class).
    RobotId => "robot/$defs/robot_id"
);
contract_ref!(
    /// Why a trial was made: `use`, `experiment` or `test`.
    Purpose => "trial/properties/purpose"
);
contract_ref!(
    /// The robot's own verdict on an attempt.
    Outcome => "trial/properties/outcome"
);

/// A task's state: the names of `pps_schema::TaskState`.
#[derive(Debug)]
pub struct TaskState;

impl JsonSchema for TaskState {
    fn inline_schema() -> bool {
        true
    }

    fn schema_name() -> Cow<'static, str> {
        "task_state".into()
    }

    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({ "enum": pps_schema::TaskState::NAMES })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_point_into_the_components() {
        let epc = Epc::json_schema(&mut SchemaGenerator::default());
        let reference = epc.get("$ref").and_then(|r| r.as_str());
        assert_eq!(reference, Some(format!("{SCHEMAS}tag/$defs/epc").as_str()));
    }
}
