//! A click answered in process on a rendered scene delivered as ROS 2 messages: the same answer
//! as `pps-robot`'s chain on the same data, and each unusable input refused in words.

use std::sync::Arc;

use pps_robot::navigation::{ApproachParams, plan_approach};
use pps_robot::perception::DepthNoise;
use pps_robot::sim::{
    AlignedDepth, CaptureSettings, DeviceKind, Room, SceneCapture, StartDirection, capture_scene,
};
use pps_ros2::InputError;
use pps_ros2::camera::camera_info;
use pps_ros2::click::{RangeInput, SensorState, answer_click};
use pps_ros2::depth::{depth_frame, depth_message};
use pps_ros2::image::image_message;
use pps_ros2::msg::builtin::Header;
use pps_ros2::msg::geometry::{Point, PointStamped, Transform, TransformStamped};
use pps_ros2::msg::sensor::Image;
use pps_ros2::msg::tf::TfMessage;

fn header(frame: &str) -> Header {
    Header { frame_id: frame.into(), ..Header::default() }
}

fn scene() -> SceneCapture {
    capture_scene(
        Room::paper(),
        DeviceKind::Drawer,
        StartDirection::Right,
        1.5,
        5,
        &CaptureSettings::small(),
    )
}

/// The scene as the node holds it after its topics arrived, the camera two static transforms
/// below the base (head, then optical frame).
fn state(scene: &SceneCapture) -> SensorState {
    let mut state = SensorState {
        image: Some(Arc::new(image_message(&scene.image, header("head_camera_optical")))),
        camera_info: Some(Arc::new(camera_info(
            &scene.calibration.intrinsics,
            header("head_camera_optical"),
        ))),
        range: Some(RangeInput::Cloud(Arc::new(scene.cloud.clone()))),
        ..SensorState::default()
    };
    let base_from_head = nalgebra::Isometry3::translation(0.1, 0.0, 1.0);
    let head_from_camera = base_from_head.inverse() * scene.calibration.base_from_camera;
    let stamped = |parent: &str, child: &str, iso| TransformStamped {
        header: header(parent),
        child_frame_id: child.into(),
        transform: Transform::from_isometry(&iso),
    };
    state.transforms.insert(&TfMessage {
        transforms: vec![
            stamped("head", "head_camera_optical", head_from_camera),
            stamped("base_link", "head", base_from_head),
        ],
    });
    state
}

fn click(scene: &SceneCapture) -> PointStamped {
    PointStamped { header: header("base_link"), point: Point::from(scene.target) }
}

#[test]
fn the_answer_is_the_chain_of_pps_robot_on_the_same_data() {
    let scene = scene();
    let params = ApproachParams::default();
    let answer = answer_click(&state(&scene), &click(&scene), "base_link", &params, None).unwrap();
    let direct =
        plan_approach(&scene.image, &scene.cloud, &scene.calibration, &scene.target, &params)
            .unwrap();
    let tag = direct.tag.as_ref().unwrap().nearest();
    let pose = answer.tag_pose.expect("a tag pose");
    assert_eq!(pose.header.frame_id, "base_link");
    let at = nalgebra::Point3::from(pose.pose.position);
    assert!((at - tag.centroid).norm() < 1e-9, "{at} vs {}", tag.centroid);
    assert!((at - scene.tag_truth).norm() < 0.03);
    let goal = answer.goal_pose.expect("a goal");
    let waypoint = direct.waypoint.unwrap();
    assert!((goal.pose.position.x - waypoint.position.x).abs() < 1e-9);
    assert!((goal.pose.position.y - waypoint.position.y).abs() < 1e-9);
    assert_eq!(answer.markers.markers[0].action, pps_ros2::msg::visualization::Marker::DELETEALL);
}

/// Where a click sends the robot, the range sensor's noise stated or not: the tag's position
/// and the goal's.
fn destination(state: &SensorState, scene: &SceneCapture, noise: Option<DepthNoise>) -> [f64; 5] {
    let params = ApproachParams::default();
    let answer = answer_click(state, &click(scene), "base_link", &params, noise).unwrap();
    let tag = answer.tag_pose.expect("a tag pose").pose.position;
    let goal = answer.goal_pose.expect("a goal").pose;
    [tag.x, tag.y, tag.z, goal.position.x, goal.position.y]
}

#[test]
fn aligned_depth_gives_the_answer_of_the_same_frame_as_a_cloud() {
    let scene = scene();
    let depth = AlignedDepth::of(&scene, &Room::paper());
    let mut from_cloud = state(&scene);
    from_cloud.range = Some(RangeInput::Cloud(Arc::new(depth.cloud.clone())));
    // The same rays as a cloud, planned with the noise a depth image is planned with by default.
    let expected = destination(&from_cloud, &scene, Some(DepthNoise::d435()));
    let (width, height) = (depth.width, depth.height);
    let millimetres =
        depth_message(width, height, &depth.millimetres(), header("head_camera_optical"));
    let metres = Image {
        encoding: "32FC1".into(),
        step: width * 4,
        data: depth.metres.iter().flat_map(|m| m.to_le_bytes()).collect(),
        ..millimetres.clone()
    };
    for message in [millimetres, metres] {
        let encoding = message.encoding.clone();
        let mut from_depth = state(&scene);
        from_depth.range = Some(RangeInput::Depth(Arc::new(depth_frame(message).unwrap())));
        from_depth.depth_info = Some(Arc::new(camera_info(
            &scene.calibration.intrinsics,
            header("head_camera_optical"),
        )));
        let got = destination(&from_depth, &scene, None);
        let worst = got.iter().zip(&expected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-3, "{encoding}: {got:?} against {expected:?}");
        from_depth.depth_info = None;
        let refused = answer_click(
            &from_depth,
            &click(&scene),
            "base_link",
            &ApproachParams::default(),
            None,
        );
        assert_eq!(refused.unwrap_err(), InputError::Missing("depth camera info"));
    }
}

#[test]
fn unusable_inputs_are_refused_in_words() {
    let scene = scene();
    let params = ApproachParams::default();
    let mut no_transform = state(&scene);
    no_transform.transforms = Default::default();
    let refused =
        answer_click(&no_transform, &click(&scene), "base_link", &params, None).unwrap_err();
    assert!(matches!(refused, InputError::NoTransform { .. }));
    assert!(refused.to_string().contains("`head_camera_optical`"), "{refused}");

    let mut mono = state(&scene);
    let mut image = (**mono.image.as_ref().unwrap()).clone();
    image.encoding = "mono8".into();
    mono.image = Some(Arc::new(image));
    let refused = answer_click(&mono, &click(&scene), "base_link", &params, None).unwrap_err();
    assert_eq!(refused, InputError::ImageEncoding("mono8".into()));

    let mut resized = state(&scene);
    let mut info = (**resized.camera_info.as_ref().unwrap()).clone();
    info.width *= 2;
    resized.camera_info = Some(Arc::new(info));
    let refused = answer_click(&resized, &click(&scene), "base_link", &params, None).unwrap_err();
    assert!(matches!(refused, InputError::SizeMismatch { .. }), "{refused}");

    let mut nowhere = click(&scene);
    nowhere.point.x = f64::NAN;
    assert_eq!(
        answer_click(&state(&scene), &nowhere, "base_link", &params, None).unwrap_err(),
        InputError::ClickNotFinite
    );

    let mut no_image = state(&scene);
    no_image.image = None;
    let refused = answer_click(&no_image, &click(&scene), "base_link", &params, None).unwrap_err();
    assert_eq!(refused.to_string(), "a point was clicked before any camera image arrived");
}
