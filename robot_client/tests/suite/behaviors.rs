//! Each behaviour in the simulator, through the hardware traits only: its success path, and
//! its failure path with the failure detected (the lamp unplugged, the drawer stuck, the object
//! sticky, the tag not where it was seen). The simulator's truth is read here, by the test, to
//! check the behaviour's verdict; the behaviours never see it.

use nalgebra::{Isometry2, Vector2};
use pps_robot::behaviors::{
    DropGeometry, ForceRecorder, RobotBody, WantedLight, drop_object, operate_light_switch,
    pull_back, pull_lamp, push,
};
use pps_robot::hal::{Arm, Carriage, Clock, Gripper, LookDirection};
use pps_robot::sim::{DeviceKind, Room, Scenario, SimClock, SimRobot, StartDirection, start_pose};
use pps_schema::{BehaviorParams, Outcome, StateChange, TagEntry};
use serde_json::json;

/// The seed entry's parameters for `key`, as the registry merges them for an EL-E.
fn params(device: DeviceKind, key: &str) -> BehaviorParams {
    let text = match device {
        DeviceKind::LightSwitch => include_str!("../../../seed_tags/light_switch.json"),
        DeviceKind::AdaLightSwitch => include_str!("../../../seed_tags/ada_light_switch.json"),
        DeviceKind::Lamp => include_str!("../../../seed_tags/lamp.json"),
        DeviceKind::Drawer => include_str!("../../../seed_tags/drawer.json"),
        DeviceKind::TrashCan => include_str!("../../../seed_tags/trash_can.json"),
    };
    let entry: TagEntry = serde_json::from_str(text).unwrap();
    entry.behaviors[key].params_for(Some("el-e"), "el-e-1").unwrap()
}

/// The robot as phase 3 leaves it: 50 cm out in front of the tag, facing it, the hand at the
/// tag's height with the fingertips about 10 cm from it.
fn robot_at(device: DeviceKind, scenario: Scenario) -> SimRobot {
    let room = Room::paper();
    let d = room.device(device);
    let pose = start_pose(d, StartDirection::Front, 0.5 + scenario.drawer_open);
    let height = d.tag_center.z;
    let robot = SimRobot::with_scenario(room, pose, 3, scenario);
    robot.move_to_height(height, f64::INFINITY).unwrap();
    if !scenario.object_in_hand {
        robot.set_opening(0.0, f64::INFINITY).unwrap();
    }
    robot.move_to_extension(0.05, f64::INFINITY).unwrap();
    robot
}

/// The simulator's own time, from a fixed epoch: the behaviours' timing is part of what is
/// tested, and must not depend on how fast the host runs.
fn sim_clock(robot: &SimRobot) -> SimClock {
    SimClock::new(robot.clone(), time::macros::datetime!(2026-01-01 00:00 UTC))
}

fn recorder<'a>(robot: &'a SimRobot, clock: &'a SimClock) -> ForceRecorder<'a> {
    ForceRecorder::new(robot, clock, clock.now())
}

fn switch(
    device: DeviceKind,
    key: &str,
    wanted: WantedLight,
    light_on: bool,
) -> (SimRobot, pps_robot::behaviors::BehaviorReport) {
    let robot = robot_at(device, Scenario { ceiling_light_on: light_on, ..Scenario::office() });
    let BehaviorParams::LightSwitch(p) = params(device, key) else { panic!() };
    let clock = sim_clock(&robot);
    let report =
        operate_light_switch(&robot, &p, LookDirection::Up, wanted, recorder(&robot, &clock))
            .unwrap();
    (robot, report)
}

#[test]
fn rocker_switch_turns_the_ceiling_light_on_and_off_and_sees_it() {
    let (robot, on) = switch(DeviceKind::AdaLightSwitch, "push_top", WantedLight::On, false);
    assert_eq!(on.outcome, Outcome::Success, "{on:#?}");
    assert_eq!(on.detector["saw"], json!("turned_on"));
    assert!(on.detector["brightness_difference"].as_f64().unwrap() < 0.0, "brighter after");
    assert!(robot.truth().ceiling_light_on);
    assert!(!on.forces.is_empty(), "finger forces recorded");

    let (robot, off) = switch(DeviceKind::AdaLightSwitch, "push_bottom", WantedLight::Off, true);
    assert_eq!(off.outcome, Outcome::Success, "{off:#?}");
    assert_eq!(off.detector["saw"], json!("turned_off"));
    assert!(!robot.truth().ceiling_light_on);
}

#[test]
fn flip_switch_sweeps_the_toggle_up_and_down() {
    let (robot, on) = switch(DeviceKind::LightSwitch, "flip_up", WantedLight::On, false);
    assert_eq!(on.outcome, Outcome::Success, "{on:#?}");
    assert!(robot.truth().ceiling_light_on && robot.truth().flip_switch_up);
    let (robot, off) = switch(DeviceKind::LightSwitch, "flip_down", WantedLight::Off, true);
    assert_eq!(off.outcome, Outcome::Success, "{off:#?}");
    assert!(!robot.truth().ceiling_light_on);
}

#[test]
fn pressing_the_wrong_half_is_a_detected_failure() {
    // The light is already on and the person asks for on: pressing the top changes nothing.
    let (robot, report) = switch(DeviceKind::AdaLightSwitch, "push_top", WantedLight::On, true);
    assert_eq!(report.outcome, Outcome::Failure, "{report:#?}");
    assert_eq!(report.detector["saw"], json!("unchanged"));
    assert!(robot.truth().ceiling_light_on);
}

#[test]
fn a_tag_moved_out_of_reach_is_a_detected_failure() {
    // The switch was seen here, but the hand is 30 cm below it: it presses bare wall.
    let robot = robot_at(DeviceKind::AdaLightSwitch, Scenario::default());
    let height = robot.height().unwrap();
    robot.move_to_height(height - 0.3, f64::INFINITY).unwrap();
    let BehaviorParams::LightSwitch(p) = params(DeviceKind::AdaLightSwitch, "push_top") else {
        panic!()
    };
    let clock = sim_clock(&robot);
    let report = operate_light_switch(
        &robot,
        &p,
        LookDirection::Up,
        WantedLight::On,
        recorder(&robot, &clock),
    )
    .unwrap();
    assert_eq!(report.outcome, Outcome::Failure, "{report:#?}");
    assert_eq!(report.detector["saw"], json!("unchanged"));
    assert!(!robot.truth().ceiling_light_on);

    // Turned away from the wall: nothing within reach at all.
    let robot = robot_at(DeviceKind::AdaLightSwitch, Scenario::default());
    {
        let mut state = robot.state();
        state.body.world_from_base *= Isometry2::new(Vector2::zeros(), std::f64::consts::PI);
    }
    let report = operate_light_switch(
        &robot,
        &p,
        LookDirection::Up,
        WantedLight::On,
        recorder(&robot, &clock),
    )
    .unwrap();
    assert_eq!(report.outcome, Outcome::Failure);
    assert_eq!(report.detector["contact"], json!(false));
}

fn lamp(scenario: Scenario) -> (SimRobot, pps_robot::behaviors::BehaviorReport) {
    let robot = robot_at(DeviceKind::Lamp, scenario);
    let BehaviorParams::PullLamp(p) = params(DeviceKind::Lamp, "pull_chain") else { panic!() };
    let clock = sim_clock(&robot);
    let report =
        pull_lamp(&robot, &p, LookDirection::Forward, WantedLight::On, recorder(&robot, &clock))
            .unwrap();
    (robot, report)
}

#[test]
fn pull_lamp_turns_the_lamp_on_and_an_unplugged_lamp_is_a_detected_failure() {
    let (robot, report) = lamp(Scenario::office());
    assert_eq!(report.outcome, Outcome::Success, "{report:#?}");
    assert_eq!(report.detector["saw"], json!("turned_on"));
    assert!(robot.truth().lamp_on);
    assert!(report.measurements["pulled"].as_f64().unwrap() > 0.0);

    let (robot, report) = lamp(Scenario { lamp_unplugged: true, ..Scenario::office() });
    assert_eq!(report.outcome, Outcome::Failure, "{report:#?}");
    assert_eq!(report.detector["saw"], json!("unchanged"));
    assert!(!robot.truth().lamp_on);
}

fn drawer_pull(stuck: bool) -> (SimRobot, pps_robot::behaviors::BehaviorReport) {
    let robot =
        robot_at(DeviceKind::Drawer, Scenario { drawer_stuck: stuck, ..Scenario::office() });
    let BehaviorParams::PullBack(p) = params(DeviceKind::Drawer, "pull_open") else { panic!() };
    let clock = sim_clock(&robot);
    let report = pull_back(&robot, &p, recorder(&robot, &clock)).unwrap();
    (robot, report)
}

#[test]
fn pull_back_opens_the_drawer_and_records_the_displacement() {
    let (robot, report) = drawer_pull(false);
    assert_eq!(report.outcome, Outcome::Success, "{report:#?}");
    let displacement = report.measurements["displacement"].as_f64().unwrap();
    assert!(displacement > 0.15, "{displacement}");
    assert!((robot.truth().drawer_open - displacement).abs() < 0.05, "{:?}", robot.truth());
    assert_eq!(report.detector["expected_distance"], json!(0.3));
}

#[test]
fn a_stuck_drawer_is_a_detected_pull_failure() {
    let (robot, report) = drawer_pull(true);
    assert_eq!(report.outcome, Outcome::Failure, "{report:#?}");
    let displacement = report.detector["displacement"].as_f64().unwrap();
    assert!(displacement < 0.15, "{displacement}");
    assert!(robot.truth().drawer_open < 0.01);
}

fn drawer_push(stuck: bool) -> (SimRobot, pps_robot::behaviors::BehaviorReport) {
    let scenario = Scenario { drawer_open: 0.3, drawer_stuck: stuck, ..Scenario::office() };
    let robot = robot_at(DeviceKind::Drawer, scenario);
    let BehaviorParams::Push(p) = params(DeviceKind::Drawer, "push_closed") else { panic!() };
    let clock = sim_clock(&robot);
    let report = push(
        &robot,
        &p,
        StateChange::Location,
        LookDirection::Forward,
        WantedLight::Changed,
        recorder(&robot, &clock),
    )
    .unwrap();
    (robot, report)
}

#[test]
fn push_closes_the_drawer_and_a_stuck_one_is_a_detected_failure() {
    let (robot, report) = drawer_push(false);
    assert_eq!(report.outcome, Outcome::Success, "{report:#?}");
    assert!(report.detector["pushed"].as_f64().unwrap() > 0.15);
    assert!(robot.truth().drawer_open < 0.05, "{:?}", robot.truth());

    let (robot, report) = drawer_push(true);
    assert_eq!(report.outcome, Outcome::Failure, "{report:#?}");
    assert_eq!(report.detector["stopped_by"], json!("stop_force"));
    assert!(robot.truth().drawer_open > 0.25);
}

fn drop_into_trash(sticky: bool) -> (SimRobot, pps_robot::behaviors::BehaviorReport) {
    let scenario = Scenario { object_in_hand: true, sticky_object: sticky, ..Scenario::office() };
    let robot = robot_at(DeviceKind::TrashCan, scenario);
    let BehaviorParams::Drop(p) = params(DeviceKind::TrashCan, "drop_in") else { panic!() };
    let tag = {
        let state = robot.state();
        state.body.world_from_base_3d().inverse()
            * state.room.device(DeviceKind::TrashCan).tag_center
    };
    let geometry = DropGeometry {
        tag,
        sweep: pps_robot::task::TaskConfig::default().drop_sweep,
        body: RobotBody::default(),
        seed: 1,
    };
    let clock = sim_clock(&robot);
    let report = drop_object(&robot, &p, &geometry, recorder(&robot, &clock)).unwrap();
    (robot, report)
}

#[test]
fn drop_releases_into_the_trash_can_and_a_sticky_object_is_a_detected_failure() {
    let (robot, report) = drop_into_trash(false);
    assert_eq!(report.outcome, Outcome::Success, "{report:#?}");
    assert_eq!(report.detector["still_held"], json!(false));
    assert!(robot.truth().object_in_trash, "{:?} {:?}", report.steps, robot.truth());

    let (robot, report) = drop_into_trash(true);
    assert_eq!(report.outcome, Outcome::Failure, "{report:#?}");
    assert_eq!(report.detector["still_held"], json!(true));
    assert!(robot.truth().object_in_hand);
}
