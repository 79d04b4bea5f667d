//! What an admin's robot registration must look like.

use pps_schema::{BehaviorKind, Robot, RobotLimits, ValidationErrors, validate_robot};
use serde_json::{Value, json};

fn el_e() -> Value {
    json!({"id": "el-e-1", "class": "el-e", "name": "EL-E",
           "capabilities": ["light_switch", "pull_back", "push", "pull_lamp", "drop"],
           "limits": {"max_force": 15.0}})
}

fn rejected(robot: &Value) -> ValidationErrors {
    validate_robot(robot).expect_err("the robot must be rejected")
}

fn pointers(errors: &ValidationErrors) -> Vec<&str> {
    errors.errors().iter().map(|e| e.pointer.as_str()).collect()
}

#[test]
fn the_design_example_validates_and_reads() {
    validate_robot(&el_e()).unwrap();
    let robot: Robot = serde_json::from_value(el_e()).unwrap();
    assert!(BehaviorKind::ALL.into_iter().all(|b| robot.can_run(b)));
    assert_eq!(robot.limits, Some(RobotLimits { max_force: Some(15.0), max_reach_height: None }));
    assert_eq!(serde_json::to_value(&robot).unwrap(), el_e());
}

#[test]
fn a_robot_without_class_or_limits_is_fine() {
    let mut robot = el_e();
    robot["class"] = Value::Null;
    robot.as_object_mut().unwrap().remove("limits");
    validate_robot(&robot).unwrap();
    let typed: Robot = serde_json::from_value(robot).unwrap();
    assert_eq!((typed.class, typed.limits), (None, None));
}

#[test]
fn last_seen_is_the_registrys_and_allowed_on_output() {
    let mut robot = el_e();
    robot["last_seen"] = json!("2024-05-01T12:00:00Z");
    validate_robot(&robot).unwrap();
    robot["last_seen"] = json!("a while ago");
    assert_eq!(pointers(&rejected(&robot)), ["/last_seen"]);
}

#[test]
fn every_problem_is_reported_at_once() {
    let robot = json!({
        "id": "EL-E-1", "class": "El E", "name": " ",
        "capabilities": ["push", "fly", "push"],
        "limits": {"max_force": 500, "max_speed": 1.0},
        "owner": "ann"
    });
    let errors = rejected(&robot);
    assert_eq!(
        pointers(&errors),
        [
            "/capabilities",
            "/capabilities/1",
            "/class",
            "/id",
            "/limits/max_force",
            "/limits/max_speed",
            "/name",
            "/owner"
        ],
        "{errors}"
    );
    let force = errors.at("/limits/max_force").next().unwrap();
    assert!(force.message.contains("500 N") && force.message.contains("100 N"), "{force}");
    let capability = errors.at("/capabilities/1").next().unwrap();
    assert!(capability.message.contains("\"pull_lamp\""), "{capability}");
}

#[test]
fn id_name_and_capabilities_are_required() {
    let errors = rejected(&json!({}));
    assert_eq!(pointers(&errors), ["/capabilities", "/id", "/name"], "{errors}");
}
