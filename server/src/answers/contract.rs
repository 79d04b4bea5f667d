//! Parts of answers whose shape the contract (`pps-schema`'s JSON Schemas) defines: their
//! schema is a `$ref` to the contract's own, never a restatement of it.

use schemars::json_schema;

/// Where the components live in the OpenAPI document.
pub const SCHEMAS: &str = "#/components/schemas/";

macro_rules! contract_ref {
    ($(#[$doc:meta])* $name:ident => $path:literal) => {
        written_schema!(
            $(#[$doc])*
            $name,
            $path,
            inline: true,
            json_schema!({ "$ref": concat!("#/components/schemas/", $path) })
        );
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

written_schema!(
    /// A task's state: the names of `pps_schema::TaskState`.
    TaskState,
    "task_state",
    inline: true,
    json_schema!({ "enum": pps_schema::TaskState::NAMES })
);

#[cfg(test)]
mod tests {
    use schemars::{JsonSchema, SchemaGenerator};

    use super::*;

    #[test]
    fn references_point_into_the_components() {
        let epc = Epc::json_schema(&mut SchemaGenerator::default());
        let reference = epc.get("$ref").and_then(|r| r.as_str());
        assert_eq!(reference, Some(format!("{SCHEMAS}tag/$defs/epc").as_str()));
    }
}
