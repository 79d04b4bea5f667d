//! A RealSense-like robot on ROS 2: colour, aligned 16-bit depth and their camera infos over
//! DDS into the `pps-ros2` process, a click, and the tag pose and goal it answers: the answer of
//! the same frame given as a cloud, to 1 mm. Inside a loopback-only network namespace.

use std::process::{Command, Stdio};
use std::time::Duration;

use crate::support::netns::isolated;
use pps_robot::navigation::{ApproachParams, plan_approach};
use pps_robot::sim::{
    AlignedDepth, CaptureSettings, DeviceKind, Room, StartDirection, capture_scene,
};
use pps_ros2::camera::camera_info;
use pps_ros2::dds::DdsSettings;
use pps_ros2::depth::depth_message;
use pps_ros2::image::image_message;
use pps_ros2::msg::RosMessage;
use pps_ros2::msg::builtin::{Header, Time};
use pps_ros2::msg::geometry::{Point, PointStamped, PoseStamped, Transform, TransformStamped};
use pps_ros2::msg::sensor::{CameraInfo, Image};
use pps_ros2::msg::tf::TfMessage;
use pps_ros2::qos;
use pps_ros2::topics::ros_name;
use ros2_client::{
    MessageTypeName, Node, NodeName, NodeOptions, Publisher, QosProfile, Subscription,
};

fn header(frame: &str) -> Header {
    Header { stamp: Time::now(), frame_id: frame.into() }
}

fn advertise<M: RosMessage>(node: &mut Node, topic: &str, qos: QosProfile) -> Publisher<M> {
    let t = node
        .create_topic(&ros_name(topic).unwrap(), MessageTypeName::new(M::PACKAGE, M::NAME), &qos)
        .unwrap();
    node.create_publisher(&t, Some(qos)).unwrap()
}

fn subscribe<M: RosMessage>(node: &mut Node, topic: &str, qos: QosProfile) -> Subscription<M> {
    let t = node
        .create_topic(&ros_name(topic).unwrap(), MessageTypeName::new(M::PACKAGE, M::NAME), &qos)
        .unwrap();
    node.create_subscription(&t, Some(qos)).unwrap()
}

#[tokio::test(flavor = "multi_thread")]
async fn aligned_depth_over_dds_gives_the_answer_of_the_same_frame_as_a_cloud() {
    if !isolated(
        "depth_over_dds::aligned_depth_over_dds_gives_the_answer_of_the_same_frame_as_a_cloud",
    ) {
        return;
    }
    let scene = capture_scene(
        Room::paper(),
        DeviceKind::Drawer,
        StartDirection::Left,
        1.5,
        4,
        &CaptureSettings::small(),
    );
    let depth = AlignedDepth::of(&scene, &Room::paper());
    let params = ApproachParams::default();
    let expected =
        plan_approach(&scene.image, &depth.cloud, &scene.calibration, &scene.target, &params)
            .unwrap();
    let tag = expected.tag.as_ref().expect("the cloud shows the tag").nearest().centroid;
    let waypoint = expected.waypoint.as_ref().expect("the cloud gives a waypoint").position;

    let state = tempfile::tempdir().unwrap();
    // No registry is needed for perception: the node starts offline and says so.
    let mut node_process = Command::new(env!("CARGO_BIN_EXE_pps-ros2"))
        .args(["--server", "http://127.0.0.1:9", "--token", "none", "--robot", "el-e-1", "--state"])
        .arg(state.path())
        .env("PPS_DDS_INTERFACE", "127.0.0.1")
        .env("RUST_LOG", "error")
        .stdin(Stdio::null())
        .spawn()
        .expect("pps-ros2 starts");
    let context =
        DdsSettings { domain_id: 0, interface: Some([127, 0, 0, 1].into()) }.context().unwrap();
    let mut node = context
        .new_node(NodeName::new("/", "realsense").unwrap(), NodeOptions::new().enable_rosout(false))
        .unwrap();
    let optical = "camera_color_optical_frame";
    let image: Publisher<Image> = advertise(&mut node, "/camera/image_raw", qos::command());
    let info: Publisher<CameraInfo> = advertise(&mut node, "/camera/camera_info", qos::command());
    let depth_image: Publisher<Image> =
        advertise(&mut node, "/camera/aligned_depth_to_color/image_raw", qos::command());
    let depth_info: Publisher<CameraInfo> =
        advertise(&mut node, "/camera/aligned_depth_to_color/camera_info", qos::command());
    let tf_static: Publisher<TfMessage> = advertise(&mut node, "/tf_static", qos::latched());
    let click: Publisher<PointStamped> = advertise(&mut node, "/clicked_point", qos::command());
    let tag_pose: Subscription<PoseStamped> = subscribe(&mut node, "/pps/tag_pose", qos::command());
    let goal: Subscription<PoseStamped> = subscribe(&mut node, "/goal_pose", qos::command());
    let spinner = node.spinner().unwrap();
    tokio::spawn(spinner.spin());
    tf_static
        .publish(TfMessage {
            transforms: vec![TransformStamped {
                header: header("base_link"),
                child_frame_id: optical.into(),
                transform: Transform::from_isometry(&scene.calibration.base_from_camera),
            }],
        })
        .unwrap();
    let intrinsics = &scene.calibration.intrinsics;
    let millimetres = depth.millimetres();
    // Until the node answers, keep the sensors coming (a best-effort sample may be lost).
    let deadline = tokio::time::Instant::now() + Duration::from_secs(60);
    let (tag_at, goal_at) = loop {
        assert!(tokio::time::Instant::now() < deadline, "pps-ros2 never answered a click");
        info.publish(camera_info(intrinsics, header(optical))).unwrap();
        depth_info.publish(camera_info(intrinsics, header(optical))).unwrap();
        image.publish(image_message(&scene.image, header(optical))).unwrap();
        depth_image
            .publish(depth_message(depth.width, depth.height, &millimetres, header(optical)))
            .unwrap();
        click
            .publish(PointStamped { header: header("base_link"), point: Point::from(scene.target) })
            .unwrap();
        let answered = tokio::time::timeout(Duration::from_secs(2), async {
            let (tag, _) = tag_pose.async_take().await.expect("a readable tag pose");
            let (goal, _) = goal.async_take().await.expect("a readable goal");
            (tag, goal)
        })
        .await;
        if let Ok(answer) = answered {
            break answer;
        }
    };
    let _ = node_process.kill();
    let _ = node_process.wait();
    let p = tag_at.pose.position;
    let off = (nalgebra::Point3::new(p.x, p.y, p.z) - tag).norm();
    assert!(off < 1e-3, "the tag from depth is {off} m from the tag from the cloud");
    let g = goal_at.pose.position;
    let off = ((g.x - waypoint.x).powi(2) + (g.y - waypoint.y).powi(2)).sqrt();
    assert!(off < 1e-3, "the goal from depth is {off} m from the goal from the cloud");
}
