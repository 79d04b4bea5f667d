//! A RealSense-like robot on ROS 2: colour, aligned 16-bit depth and their camera infos over
//! DDS into the `pps-ros2` process, a click, and the tag pose and goal it answers: the answer
//! `pps-robot perceive --depth` gives on the same frame, to 1 mm. The frame is a D435's at
//! 3.5 m, its depth scattered as the camera's is, where planning with a laser's noise loses the
//! drawer's front. Inside a loopback-only network namespace.

use std::process::{Child, Command, Stdio};
use std::time::Duration;

use crate::support::netns::isolated;
use pps_robot::navigation::{ApproachParams, ApproachPlan, plan_approach_on_depth};
use pps_robot::perception::{DepthNoise, DepthRange};
use pps_robot::sim::{
    AlignedDepth, CaptureSettings, DeviceKind, Room, SceneCapture, StartDirection, capture_scene,
    head_camera,
};
use pps_ros2::camera::camera_info;
use pps_ros2::dds::DdsSettings;
use pps_ros2::depth::{DepthFrame, depth_frame, depth_message};
use pps_ros2::image::image_message;
use pps_ros2::msg::builtin::{Header, Time};
use pps_ros2::msg::geometry::{Point, PointStamped, PoseStamped, Transform, TransformStamped};
use pps_ros2::msg::sensor::{CameraInfo, Image};
use pps_ros2::msg::tf::TfMessage;
use pps_ros2::qos;
use pps_ros2::topics::{advertise, subscribe};
use rand::{Rng, SeedableRng};
use ros2_client::{NodeName, NodeOptions, Publisher, Subscription};

fn header(frame: &str) -> Header {
    Header { stamp: Time::now(), frame_id: frame.into() }
}

/// The drawer seen from 3.5 m by a 640×480 camera whose depth scatters as a D435's does
/// (σ of 4.8 cm there), in whole millimetres as `aligned_depth_to_color` publishes it.
fn d435_frame_at_three_and_a_half_metres() -> (SceneCapture, AlignedDepth) {
    let settings = CaptureSettings { camera: head_camera(0.5), ..CaptureSettings::small() };
    let scene =
        capture_scene(Room::paper(), DeviceKind::Drawer, StartDirection::Left, 3.5, 4, &settings);
    let mut depth = AlignedDepth::of(&scene, &Room::paper());
    let noise = DepthNoise::d435();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    for z in depth.metres.iter_mut().filter(|z| z.is_finite()) {
        // A standard normal sample (Box–Muller).
        let u: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
        let normal = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * rng.random::<f64>()).cos();
        *z += (noise.sigma_at(f64::from(*z)) * normal) as f32;
    }
    (scene, depth)
}

/// A process stopped when the test ends, also when it fails.
struct Stopped(Child);

impl Drop for Stopped {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// What `pps-robot perceive --depth` plans on `depth` with the noise model `noise`.
fn perceive_depth(scene: &SceneCapture, depth: &DepthFrame, noise: DepthNoise) -> ApproachPlan {
    let params = ApproachParams { depth_noise: noise, ..ApproachParams::default() };
    let range = DepthRange::default();
    let (image, calibration) = (&scene.image, &scene.calibration);
    plan_approach_on_depth(image, &depth.image, calibration, &scene.target, &range, &params)
        .unwrap()
}

#[tokio::test(flavor = "multi_thread")]
async fn aligned_depth_over_dds_gives_perceive_s_answer_with_the_camera_s_noise() {
    if !isolated(
        "depth_over_dds::aligned_depth_over_dds_gives_perceive_s_answer_with_the_camera_s_noise",
    ) {
        return;
    }
    let (scene, depth) = d435_frame_at_three_and_a_half_metres();
    let optical = "camera_color_optical_frame";
    let millimetres = depth.millimetres();
    let frame =
        depth_frame(depth_message(depth.width, depth.height, &millimetres, header(optical)))
            .unwrap();
    // `perceive --depth` without --depth-noise-at-1m: a D435's noise.
    let expected = perceive_depth(&scene, &frame, DepthNoise::stated_or_typical(None, true));
    let tag = expected.tag.as_ref().expect("perceive finds the tag").nearest().centroid;
    assert!((tag - scene.tag_truth).norm() < 0.02, "{tag} is not at the truth {}", scene.tag_truth);
    let waypoint = expected.waypoint.as_ref().expect("perceive gives a waypoint").position;
    // Where the laser's noise would be planned with, the front is lost: the range matters.
    let as_laser = perceive_depth(&scene, &frame, DepthNoise::LASER);
    assert!(as_laser.waypoint.is_none(), "at 3.5 m the laser's tolerances find no front");

    let state = tempfile::tempdir().unwrap();
    // No registry is needed for perception: the node starts offline and says so.
    let _node_process = Stopped(
        Command::new(env!("CARGO_BIN_EXE_pps-ros2"))
            .args([
                "--server",
                "http://127.0.0.1:9",
                "--token",
                "none",
                "--robot",
                "el-e-1",
                "--state",
            ])
            .arg(state.path())
            .env("PPS_DDS_INTERFACE", "127.0.0.1")
            .env("RUST_LOG", "error")
            .stdin(Stdio::null())
            .spawn()
            .expect("pps-ros2 starts"),
    );
    let context =
        DdsSettings { domain_id: 0, interface: Some([127, 0, 0, 1].into()) }.context().unwrap();
    let mut node = context
        .new_node(NodeName::new("/", "realsense").unwrap(), NodeOptions::new().enable_rosout(false))
        .unwrap();
    let image: Publisher<Image> =
        advertise(&mut node, "/camera/image_raw", qos::command()).unwrap();
    let info: Publisher<CameraInfo> =
        advertise(&mut node, "/camera/camera_info", qos::command()).unwrap();
    let depth_image: Publisher<Image> =
        advertise(&mut node, "/camera/aligned_depth_to_color/image_raw", qos::command()).unwrap();
    let depth_info: Publisher<CameraInfo> =
        advertise(&mut node, "/camera/aligned_depth_to_color/camera_info", qos::command()).unwrap();
    let tf_static: Publisher<TfMessage> =
        advertise(&mut node, "/tf_static", qos::latched()).unwrap();
    let click: Publisher<PointStamped> =
        advertise(&mut node, "/clicked_point", qos::command()).unwrap();
    let tag_pose: Subscription<PoseStamped> =
        subscribe(&mut node, "/pps/tag_pose", qos::command()).unwrap();
    let goal: Subscription<PoseStamped> =
        subscribe(&mut node, "/goal_pose", qos::command()).unwrap();
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
    // Until the node answers, keep the sensors coming (a best-effort sample may be lost).
    let deadline = tokio::time::Instant::now() + Duration::from_secs(60);
    let tag_at = loop {
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
        let answered = tokio::time::timeout(Duration::from_secs(2), tag_pose.async_take()).await;
        if let Ok(answer) = answered {
            break answer.expect("a readable tag pose").0;
        }
    };
    let p = tag_at.pose.position;
    let off = (nalgebra::Point3::new(p.x, p.y, p.z) - tag).norm();
    assert!(off < 1e-3, "the node's tag is {off} m from perceive's");
    // The goal is published right after the tag's pose.
    let goal_at = tokio::time::timeout(Duration::from_secs(10), goal.async_take())
        .await
        .expect("the tag's pose came without a goal")
        .expect("a readable goal")
        .0;
    let g = goal_at.pose.position;
    let off = ((g.x - waypoint.x).powi(2) + (g.y - waypoint.y).powi(2)).sqrt();
    assert!(off < 1e-3, "the node's goal is {off} m from perceive's waypoint");
}

#[test]
fn a_noise_no_depth_camera_has_is_refused_in_one_sentence() {
    if !isolated("depth_over_dds::a_noise_no_depth_camera_has_is_refused_in_one_sentence") {
        return;
    }
    let refusals = [
        (
            "0.5",
            "error: invalid value '0.5' for '--depth-noise-at-1m <METRES>': 0.5 m is not a depth camera's noise at 1 m: give a σ between 0 and 0.1 m (a RealSense D435 has about 0.0036)",
        ),
        ("0", "0 m is not a depth camera's noise at 1 m"),
        ("much", "`much` is not a number"),
    ];
    for (given, said) in refusals {
        let output = Command::new(env!("CARGO_BIN_EXE_pps-ros2"))
            .args(["--server", "http://127.0.0.1:9", "--token", "none", "--robot", "el-e-1"])
            .args(["--depth-noise-at-1m", given])
            .stdin(Stdio::null())
            .output()
            .expect("pps-ros2 runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{given} was taken");
        assert!(stderr.contains(said), "{given}: {stderr}");
    }
}
