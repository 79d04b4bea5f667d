//! Navigation geometry (paper §IV-B.1) on rendered scenes, and the finger RFID choice.

use nalgebra::{Isometry2, Point3, Vector2, Vector3};
use pps_robot::hal::{Arm, Carriage, RfidReader};
use pps_robot::navigation::{
    ApproachParams, Clearance, RfidIdentity, choose_backing_plane, identify_tag,
    nearest_plane_to_target, plan_approach,
};
use pps_robot::sim::{
    CaptureSettings, DeviceKind, Room, RoomOptions, SimRobot, StartDirection, capture_scene,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn approach_is_perpendicular_to_the_surface_behind_the_tag_from_every_start() {
    for device in DeviceKind::ALL {
        for (direction, seed) in
            StartDirection::PAPER.into_iter().flat_map(|d| (0..3).map(move |s| (d, s)))
        {
            let scene = capture_scene(
                Room::paper(),
                device,
                direction,
                1.5,
                seed,
                &CaptureSettings::small(),
            );
            let plan = plan_approach(
                &scene.image,
                &scene.cloud,
                &scene.calibration,
                &scene.target,
                &ApproachParams::default(),
            )
            .expect("consistent inputs");
            let what = format!("{device:?} from {direction:?}, seed {seed}");
            let plane = plan.backing_plane.unwrap_or_else(|| panic!("{what}: no backing plane"));
            assert!(
                plane.normal.dot(&scene.tag_normal) > 10f64.to_radians().cos(),
                "{what}: {plane:?}"
            );
            let waypoint = plan.waypoint.expect("a waypoint");
            let tag = plan.tag.expect("a tag").nearest().centroid;
            let out = waypoint.position - tag;
            assert!((Vector2::new(out.x, out.y).norm() - 0.5).abs() < 1e-9, "{what}: 50 cm out");
            let facing = Vector2::new(waypoint.yaw.cos(), waypoint.yaw.sin());
            assert!(
                facing.dot(&-Vector2::new(out.x, out.y).normalize()) > 0.999,
                "{what}: faces the tag"
            );
            assert_eq!(plan.clearance, Some(Clearance::Clear), "{what}");
        }
    }
}

/// Oblique starts at the drawer with the person's target at the front's edge on the robot's
/// side, where the side face comes as near as the front. The paper's nearest-plane rule then
/// takes the side face for some targets; the backing-plane rule never does.
#[test]
fn drawer_front_is_chosen_where_the_nearest_plane_picks_the_side_face() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let (mut trials, mut paper_wrong) = (0, 0);
    for direction in [StartDirection::FarLeft, StartDirection::FarRight] {
        let scene = capture_scene(
            Room::paper(),
            DeviceKind::Drawer,
            direction,
            1.5,
            2,
            &CaptureSettings::small(),
        );
        let normal = scene.tag_normal;
        let lateral = normal.cross(&Vector3::z());
        let robot = Point3::from(scene.calibration.base_from_camera.translation.vector);
        let side = (robot - scene.tag_truth).dot(&lateral).signum();
        // The towel hangs 3 cm proud of the drawer front, whose edge is 20.5 cm from its centre.
        let edge = scene.tag_truth - normal * 0.03 + lateral * side * 0.205;
        let params = ApproachParams::default();
        for _ in 0..20 {
            let noise = Vector3::new(
                rng.random_range(-0.03..0.03),
                rng.random_range(-0.03..0.03),
                rng.random_range(-0.05..0.05),
            );
            let target = edge + noise;
            let plan =
                plan_approach(&scene.image, &scene.cloud, &scene.calibration, &target, &params)
                    .expect("consistent inputs");
            let tag = plan.tag.as_ref().expect("the towel is within reach of the target").nearest();
            // Both rules judge the planes the search found around the tag.
            let (planes, points) = (&plan.planes, &plan.surface_points);
            let ours = choose_backing_plane(
                planes,
                points,
                &tag.centroid,
                tag.radius,
                &tag.members,
                &robot,
                &params.backing,
            )
            .plane
            .expect("a backing plane");
            assert!(ours.normal.dot(&normal) > 0.98, "{direction:?}: ours took {ours:?}");
            let paper = nearest_plane_to_target(planes, points, &target).expect("some plane");
            trials += 1;
            if paper.normal.dot(&normal) < 0.5 {
                paper_wrong += 1;
            }
        }
    }
    assert!(
        paper_wrong * 10 >= trials,
        "the paper's rule took the side face in only {paper_wrong} of {trials}"
    );
}

/// The robot's fingers 8–12 cm in front of the flip switch's tag, the rocker switch's tag 30 cm
/// away: the strongest read names the right tag or says it cannot tell, never the wrong one.
#[test]
fn rfid_names_the_tag_at_the_fingers_or_says_it_is_ambiguous() {
    let room = Room::new(RoomOptions { switch_spacing: 0.3, ..RoomOptions::default() });
    let flip = room.device(DeviceKind::LightSwitch).clone();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let (mut identified, mut ambiguous) = (0, 0);
    for trial in 0..100 {
        let standoff = rng.random_range(0.08..0.12);
        let sideways = rng.random_range(-0.04..0.04);
        // Base centre such that the fingertips (base front 25 cm + extension 20 cm + fingers 10 cm)
        // stop `standoff` short of the tag, facing the wall.
        let reach = 0.25 + 0.20 + 0.10;
        let at = flip.tag_center
            + flip.tag_normal * (standoff + reach)
            + flip.tag_normal.cross(&Vector3::z()) * sideways;
        let yaw = (-flip.tag_normal.y).atan2(-flip.tag_normal.x);
        let robot =
            SimRobot::new(room.clone(), Isometry2::new(Vector2::new(at.x, at.y), yaw), trial);
        robot.move_to_height(flip.tag_center.z, 100.0).expect("within travel");
        robot.move_to_extension(0.20, 100.0).expect("within travel");
        let reads: Vec<_> = (0..5).flat_map(|_| robot.inventory().expect("reader works")).collect();
        match identify_tag(&reads, 3.0).expect("the tag in front answers") {
            RfidIdentity::Identified(signal) => {
                assert_eq!(signal.epc, DeviceKind::LightSwitch.epc(), "trial {trial}");
                identified += 1;
            }
            RfidIdentity::Ambiguous { strongest, runner_up } => {
                assert!([&strongest.epc, &runner_up.epc].contains(&&DeviceKind::LightSwitch.epc()));
                ambiguous += 1;
            }
        }
    }
    assert!(identified >= 90, "{identified} identified, {ambiguous} ambiguous");
}

#[test]
fn fingers_midway_between_two_tags_cannot_tell() {
    let room = Room::new(RoomOptions { switch_spacing: 0.3, ..RoomOptions::default() });
    let (a, b) = (
        room.device(DeviceKind::LightSwitch).clone(),
        room.device(DeviceKind::AdaLightSwitch).clone(),
    );
    let midway = nalgebra::center(&a.tag_center, &b.tag_center);
    let at = midway + a.tag_normal * (0.10 + 0.55);
    let yaw = (-a.tag_normal.y).atan2(-a.tag_normal.x);
    let mut ambiguous = 0;
    for trial in 0..50 {
        let robot =
            SimRobot::new(room.clone(), Isometry2::new(Vector2::new(at.x, at.y), yaw), trial);
        robot.move_to_height(midway.z, 100.0).expect("within travel");
        robot.move_to_extension(0.20, 100.0).expect("within travel");
        let reads: Vec<_> = (0..5).flat_map(|_| robot.inventory().expect("reader works")).collect();
        if matches!(identify_tag(&reads, 3.0), Some(RfidIdentity::Ambiguous { .. })) {
            ambiguous += 1;
        }
    }
    assert!(ambiguous >= 40, "only {ambiguous} of 50 midway reads were ambiguous");
}
