//! The simulated devices respond to the robot's hands as the real ones do: switches toggle the
//! lights past their force and travel, the drawer slides or sticks, the lamp clicks, objects drop
//! or stick. Everything is driven through the hardware traits; `truth()` only checks the result.

use nalgebra::{Isometry2, Point3, Vector2, Vector3};
use pps_robot::hal::{
    Arm, BrightnessCamera, Carriage, Finger, FingerForceTorque, Gripper, LookDirection, MobileBase,
    PalmRange,
};
use pps_robot::sim::{BodyGeometry, DeviceKind, Room, Scenario, SimRobot};

/// A robot whose palm is `palm_distance` metres out from `point` along `normal`, at the point's
/// height, facing it, the arm retracted.
fn robot_facing(
    point: Point3<f64>,
    normal: Vector3<f64>,
    palm_distance: f64,
    scenario: Scenario,
) -> SimRobot {
    let reach = palm_distance + BodyGeometry::default().base_front;
    let at = Vector2::new(point.x + normal.x * reach, point.y + normal.y * reach);
    let pose = Isometry2::new(at, (-normal.y).atan2(-normal.x));
    let robot = SimRobot::with_scenario(Room::paper(), pose, 7, scenario);
    robot.move_to_height(point.z, 50.0).unwrap();
    robot
}

fn device(kind: DeviceKind) -> (Point3<f64>, Vector3<f64>) {
    let room = Room::paper();
    let d = room.device(kind);
    (d.tag_center, d.tag_normal)
}

fn finger_forces(robot: &SimRobot) -> [f64; 2] {
    [Finger::Left, Finger::Right].map(|f| robot.wrench(f).unwrap().force_magnitude())
}

#[test]
fn pressing_the_rocker_top_turns_the_ceiling_light_on_and_the_camera_sees_it() {
    let (tag, normal) = device(DeviceKind::AdaLightSwitch);
    let top = tag + Vector3::z() * 0.02;
    let robot = robot_facing(top, normal, 0.15, Scenario::default());
    robot.set_opening(5f64.to_radians(), 10.0).unwrap();
    let dark = robot.mean_intensity(LookDirection::Up).unwrap();
    assert!(!robot.truth().ceiling_light_on && !robot.truth().rocker_top_pressed);

    // A touch below the snap force rocks the paddle but does not switch it.
    let touched = robot.move_to_extension(0.2, 2.0).unwrap();
    assert!(touched < 0.1, "the arm stopped on the paddle at {touched}");
    assert!(!robot.truth().ceiling_light_on);

    let pressed = robot.move_to_extension(0.2, 3.0).unwrap();
    assert!(pressed > touched && pressed < 0.1, "pressed in to {pressed}");
    let truth = robot.truth();
    assert!(truth.ceiling_light_on && truth.rocker_top_pressed);
    assert!(
        finger_forces(&robot).iter().any(|&f| f > 2.5),
        "the fingers still press after the snap"
    );
    let lit = robot.mean_intensity(LookDirection::Up).unwrap();
    assert!(lit > dark + 20.0, "brightness up {dark:.1} -> {lit:.1}");

    // Pressing the top again meets the pressed paddle's stop and changes nothing.
    robot.move_to_extension(0.0, 50.0).unwrap();
    robot.move_to_extension(0.2, 3.0).unwrap();
    assert!(robot.truth().ceiling_light_on);
}

#[test]
fn a_flip_sweep_toggles_the_light_and_stops_against_the_lever() {
    let (tag, normal) = device(DeviceKind::LightSwitch);
    // The tag is the middle of the foam tube, 2.2 cm out from the wall.
    let wall = tag - normal * 0.022;
    for (light_on, sweep) in [(false, 0.15f64), (true, -0.15)] {
        let start = wall + normal * 0.025 - Vector3::z() * (0.05 * sweep.signum());
        let robot = robot_facing(
            start,
            normal,
            0.1,
            Scenario { ceiling_light_on: light_on, ..Scenario::default() },
        );
        robot.set_opening(10f64.to_radians(), 10.0).unwrap();
        assert!((robot.extension().unwrap() - 0.0).abs() < 1e-9);
        let from = robot.height().unwrap();
        let reached = robot.move_to_height(from + sweep, 12.0).unwrap();
        let truth = robot.truth();
        assert_eq!(truth.flip_switch_up, !light_on, "sweep {sweep}");
        assert_eq!(truth.ceiling_light_on, !light_on);
        assert!(
            (reached - from).abs() < 0.1,
            "stopped against the flipped lever after {:.3}",
            reached - from
        );
        assert!(finger_forces(&robot).iter().any(|&f| f > 11.0));
    }
}

/// A robot with the drawer's towel pinched in its gripper.
fn grasping_the_towel(scenario: Scenario) -> SimRobot {
    let (tag, normal) = device(DeviceKind::Drawer);
    let towel = tag + normal * (0.004 + scenario.drawer_open);
    let robot = robot_facing(towel, normal, 0.08, scenario);
    robot.set_opening(90f64.to_radians(), 10.0).unwrap();
    robot.set_opening(0.0, 4.0).unwrap();
    let [left, right] = finger_forces(&robot);
    assert!(left > 2.0 && right > 2.0, "grasped: {left:.2} {right:.2}");
    robot
}

#[test]
fn a_free_drawer_slides_to_its_stop_and_a_stuck_one_holds() {
    let robot = grasping_the_towel(Scenario::default());
    robot.drive(-0.2).unwrap();
    let opened = robot.truth().drawer_open;
    assert!((0.17..0.21).contains(&opened), "one pull step opened {opened:.3}");
    let [left, right] = finger_forces(&robot);
    assert!(left > 2.0 && right > 2.0, "still holding: {left:.2} {right:.2}");
    robot.drive(-0.2).unwrap();
    let opened = robot.truth().drawer_open;
    assert!((0.35..=0.4).contains(&opened), "at the stop: {opened:.3}");
    robot.drive(-0.1).unwrap();
    assert!((0.35..=0.4).contains(&robot.truth().drawer_open));
    let [left, right] = finger_forces(&robot);
    assert!(left < 0.5 && right < 0.5, "the towel slipped out at the stop: {left:.2} {right:.2}");

    let stuck = grasping_the_towel(Scenario { drawer_stuck: true, ..Scenario::default() });
    stuck.drive(-0.008).unwrap();
    let [left, right] = finger_forces(&stuck);
    assert!(left + right > 12.0, "a stuck drawer resists: {left:.2} {right:.2}");
    assert_eq!(stuck.truth().drawer_open, 0.0);
    stuck.drive(-0.2).unwrap();
    assert_eq!(stuck.truth().drawer_open, 0.0);
    let [left, right] = finger_forces(&stuck);
    assert!(left < 0.5 && right < 0.5, "grip lost: {left:.2} {right:.2}");
}

#[test]
fn pushing_an_open_drawer_closes_it_and_a_stuck_one_stops_the_base() {
    let (tag, normal) = device(DeviceKind::Drawer);
    for stuck in [false, true] {
        let scenario = Scenario { drawer_open: 0.3, drawer_stuck: stuck, ..Scenario::default() };
        // The front panel is 3.4 cm behind the towel the tag is on; the fingers pass the soft
        // towel and push the panel.
        let face = tag + normal * (0.3 - 0.03);
        let robot = robot_facing(face, normal, 0.2, scenario);
        let seen = robot.range().unwrap();
        assert!(seen.is_some_and(|r| r < 0.2), "the palm sees the open drawer: {seen:?}");
        robot.set_opening(90f64.to_radians(), 10.0).unwrap();
        let pushed = robot.move_to_extension(0.4, 2.0).unwrap();
        assert!(pushed < 0.2, "contact with the drawer front at {pushed:.3}");
        robot.drive(0.4).unwrap();
        let open = robot.truth().drawer_open;
        if stuck {
            assert_eq!(open, 0.3);
            assert!(finger_forces(&robot).iter().any(|&f| f > 12.0));
        } else {
            assert!(open < 0.01, "pushed closed: {open:.3}");
        }
    }
}

/// A robot with the lamp's chain foam pinched, pulling it down 7 cm.
fn pull_the_lamp(scenario: Scenario) -> (SimRobot, f64, f64) {
    let (tag, normal) = device(DeviceKind::Lamp);
    let robot = robot_facing(tag, normal, 0.08, scenario);
    robot.set_opening(30f64.to_radians(), 10.0).unwrap();
    let before = robot.mean_intensity(LookDirection::Forward).unwrap();
    robot.set_opening(0.0, 3.0).unwrap();
    let [left, right] = finger_forces(&robot);
    assert!(left > 2.0 && right > 2.0, "pinched: {left:.2} {right:.2}");
    let from = robot.height().unwrap();
    robot.move_to_height(from - 0.07, 10.0).unwrap();
    let after = robot.mean_intensity(LookDirection::Forward).unwrap();
    (robot, before, after)
}

#[test]
fn pulling_the_chain_lights_the_lamp_unless_it_is_unplugged() {
    let (robot, before, after) = pull_the_lamp(Scenario::office());
    assert!(robot.truth().lamp_on);
    assert!(after > before + 5.0, "the lamp lit: {before:.1} -> {after:.1}");

    let (robot, before, after) =
        pull_the_lamp(Scenario { lamp_unplugged: true, ..Scenario::office() });
    assert!(!robot.truth().lamp_on);
    assert!(
        (after - before).abs() < 2.0,
        "an unplugged lamp stays dark: {before:.1} -> {after:.1}"
    );
}

/// A robot holding an object above the trash can's opening.
fn over_the_trash_can(sticky: bool) -> SimRobot {
    let (tag, normal) = device(DeviceKind::TrashCan);
    // The can's middle is 12.7 cm behind its tag; the object sits 10 cm ahead of the palm.
    let middle = tag - normal * 0.127;
    let robot = robot_facing(
        middle,
        normal,
        0.1,
        Scenario { object_in_hand: true, sticky_object: sticky, ..Scenario::office() },
    );
    robot.move_to_height(0.6, 50.0).unwrap();
    robot
}

#[test]
fn a_released_object_falls_into_the_can_and_a_sticky_one_stays_in_hand() {
    let robot = over_the_trash_can(false);
    assert!(finger_forces(&robot).iter().all(|&f| f > 1.0), "holding");
    assert!(robot.range().unwrap().is_some_and(|r| r < 0.05), "the palm sees the object");
    robot.set_opening(90f64.to_radians(), 10.0).unwrap();
    let truth = robot.truth();
    assert!(truth.object_in_trash && !truth.object_in_hand);
    assert!(finger_forces(&robot).iter().all(|&f| f < 0.3));
    assert!(robot.range().unwrap().is_none_or(|r| r > 0.05));

    let sticky = over_the_trash_can(true);
    sticky.set_opening(90f64.to_radians(), 10.0).unwrap();
    let truth = sticky.truth();
    assert!(truth.object_in_hand && !truth.object_in_trash);
    assert!(finger_forces(&sticky).iter().any(|&f| f > 0.5), "its weight hangs on a finger");
    assert!(sticky.range().unwrap().is_some_and(|r| r < 0.05));
}

#[test]
fn the_arm_stops_at_a_wall_when_the_force_exceeds_its_limit() {
    // Facing the bare west wall, away from the chest and the trash can.
    let wall = Point3::new(0.0, 4.6, 1.0);
    let robot = robot_facing(wall, Vector3::x(), 0.25, Scenario::office());
    assert!(robot.range().unwrap().is_some_and(|r| (r - 0.25).abs() < 0.02));
    let reached = robot.move_to_extension(0.5, 5.0).unwrap();
    assert!((reached - 0.15).abs() < 0.01, "the fingertips reach the wall at 0.15 m: {reached:.4}");
    let [left, right] = finger_forces(&robot);
    assert!(
        left.max(right) > 4.5 && left.max(right) < 6.0,
        "pressing with about 5 N: {left:.2} {right:.2}"
    );
    // The base's own safety stops it pushing the arm through the wall.
    robot.drive(0.1).unwrap();
    assert!(finger_forces(&robot).iter().all(|&f| f < 32.0));
    assert!(robot.pose_estimate().unwrap().translation.x < 0.03);
}

#[test]
fn the_same_seed_gives_the_same_readings() {
    let readings = |seed: u64| {
        let (tag, normal) = device(DeviceKind::AdaLightSwitch);
        let at = tag + normal * 0.4;
        let pose = Isometry2::new(Vector2::new(at.x, at.y), (-normal.y).atan2(-normal.x));
        let robot = SimRobot::with_scenario(Room::paper(), pose, seed, Scenario::default());
        robot.move_to_height(1.24, 50.0).unwrap();
        robot.set_opening(0.1, 10.0).unwrap();
        robot.move_to_extension(0.2, 3.0).unwrap();
        robot.drive(-0.1).unwrap();
        (
            robot.wrench(Finger::Left).unwrap(),
            robot.range().unwrap(),
            robot.mean_intensity(LookDirection::Up).unwrap(),
            robot.pose_estimate().unwrap(),
        )
    };
    assert_eq!(readings(3), readings(3));
    assert_ne!(readings(3), readings(4));
}

#[test]
fn an_off_centre_towel_grasp_loads_the_near_finger_harder() {
    let (tag, normal) = device(DeviceKind::Drawer);
    // Facing the towel (along -normal), the robot's left is -(z × normal); the palm 3 cm to
    // the right of the towel leaves the towel on the left.
    let robots_left = -Vector3::z().cross(&normal);
    let palm_line = tag + normal * 0.004 - robots_left * 0.03;
    let robot = robot_facing(palm_line, normal, 0.08, Scenario::default());
    robot.set_opening(90f64.to_radians(), 10.0).unwrap();
    robot.set_opening(0.0, 4.0).unwrap();
    let left = robot.wrench(Finger::Left).unwrap().force;
    let right = robot.wrench(Finger::Right).unwrap().force;
    assert!(
        left.norm() > right.norm() + 1.0,
        "the left finger meets the towel first: {left:?} {right:?}"
    );
}

#[test]
fn a_hand_pressing_past_a_limit_can_still_back_away() {
    let wall = Point3::new(0.0, 4.6, 1.0);
    let robot = robot_facing(wall, Vector3::x(), 0.25, Scenario::office());
    robot.move_to_extension(0.5, 8.0).unwrap();
    let pressed = robot.extension().unwrap();
    let again = robot.move_to_extension(0.5, 2.0).unwrap();
    assert!(again - pressed < 1e-4, "no further in: {pressed} -> {again}");
    assert_eq!(robot.move_to_extension(0.0, 2.0).unwrap(), 0.0, "but all the way out");
    assert!(finger_forces(&robot).iter().all(|&f| f < 0.3));
}
