//! `cargo bench -p pps-ros2`: what the ROS 2 layer costs on the benchmark's data (a 1280×960
//! image, a ~200 000-point cloud): decoding a `PointCloud2` payload, the click's chain in
//! process, and a click to `/goal_pose` through DDS and the real `pps-ros2` process. The DDS
//! part runs, like every DDS process here, inside a loopback-only network namespace: this
//! benchmark re-runs itself inside one.

#[path = "../tests/suite/support/netns.rs"]
mod netns;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use pps_robot::navigation::ApproachParams;
use pps_robot::sim::{
    CaptureSettings, DeviceKind, Room, SceneCapture, StartDirection, capture_scene,
};
use pps_ros2::camera::camera_info;
use pps_ros2::cdr::{decode, encode};
use pps_ros2::click::{RangeInput, SensorState, answer_click};
use pps_ros2::cloud::{cloud_message, point_cloud};
use pps_ros2::dds::DdsSettings;
use pps_ros2::image::image_message;
use pps_ros2::msg::builtin::{Header, Time};
use pps_ros2::msg::geometry::{Point, PointStamped, PoseStamped, Transform, TransformStamped};
use pps_ros2::msg::sensor::{CameraInfo, Image, PointCloud2};
use pps_ros2::msg::tf::TfMessage;
use pps_ros2::qos;
use pps_ros2::topics::{advertise, subscribe};
use ros2_client::{NodeName, NodeOptions, Publisher, Subscription};

const CLICKS: usize = 20;

fn header(frame: &str) -> Header {
    Header { stamp: Time::now(), frame_id: frame.into() }
}

/// Median, 90th percentile and least of some times, milliseconds.
fn summary(mut ms: Vec<f64>) -> String {
    ms.sort_by(f64::total_cmp);
    let at = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
    format!(
        "median {:.2} ms, p90 {:.2} ms, min {:.2} ms (n = {})",
        at(0.5),
        at(0.9),
        ms[0],
        ms.len()
    )
}

fn timed<T>(runs: usize, mut f: impl FnMut() -> T) -> Vec<f64> {
    (0..runs)
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(f());
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect()
}

fn scene() -> SceneCapture {
    capture_scene(
        Room::paper(),
        DeviceKind::LightSwitch,
        StartDirection::Left,
        1.5,
        1,
        &CaptureSettings::full(),
    )
}

fn camera_transform(scene: &SceneCapture) -> TfMessage {
    TfMessage {
        transforms: vec![TransformStamped {
            header: header("base_link"),
            child_frame_id: "camera_optical".into(),
            transform: Transform::from_isometry(&scene.calibration.base_from_camera),
        }],
    }
}

/// Decoding and the chain, no DDS.
fn in_process(scene: &SceneCapture) -> f64 {
    let cloud = cloud_message(&scene.cloud, header("base_link"));
    let payload = encode(&cloud).expect("a cloud encodes");
    println!("PointCloud2 of {} points ({:.1} MB):", scene.cloud.len(), payload.len() as f64 / 1e6);
    println!(
        "  CDR payload to message: {}",
        summary(timed(50, || decode::<PointCloud2>(&payload).unwrap()))
    );
    println!("  message to points:      {}", summary(timed(50, || point_cloud(&cloud).unwrap())));
    println!(
        "  payload to points:      {}",
        summary(timed(50, || point_cloud(&decode::<PointCloud2>(&payload).unwrap()).unwrap()))
    );
    let mut state = SensorState {
        image: Some(image_message(&scene.image, header("camera_optical")).into()),
        camera_info: Some(
            camera_info(&scene.calibration.intrinsics, header("camera_optical")).into(),
        ),
        range: Some(RangeInput::Cloud(point_cloud(&cloud).unwrap().into())),
        ..SensorState::default()
    };
    state.transforms.insert(&camera_transform(scene));
    let click = PointStamped { header: header("base_link"), point: Point::from(scene.target) };
    let params = ApproachParams::default();
    let chain = timed(10, || {
        answer_click(&state, &click, "base_link", &params, None).expect("the chain runs")
    });
    let mut sorted = chain.clone();
    sorted.sort_by(f64::total_cmp);
    println!(
        "click answered in process (image conversion and the paper's chain): {}",
        summary(chain)
    );
    sorted[sorted.len() / 2]
}

/// A click to `/goal_pose` through DDS and the `pps-ros2` process, on loopback.
async fn over_dds(scene: &SceneCapture, chain_ms: f64) {
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
        .new_node(NodeName::new("/", "pps_bench").unwrap(), NodeOptions::new().enable_rosout(false))
        .unwrap();
    let image: Publisher<Image> =
        advertise(&mut node, "/camera/image_raw", qos::command()).unwrap();
    let info: Publisher<CameraInfo> =
        advertise(&mut node, "/camera/camera_info", qos::command()).unwrap();
    let points: Publisher<PointCloud2> = advertise(&mut node, "/points", qos::command()).unwrap();
    let tf_static: Publisher<TfMessage> =
        advertise(&mut node, "/tf_static", qos::latched()).unwrap();
    let click: Publisher<PointStamped> =
        advertise(&mut node, "/clicked_point", qos::command()).unwrap();
    let goal: Subscription<PoseStamped> =
        subscribe(&mut node, "/goal_pose", qos::command()).unwrap();
    let spinner = node.spinner().unwrap();
    tokio::spawn(spinner.spin());
    tf_static.publish(camera_transform(scene)).unwrap();
    let the_click =
        || PointStamped { header: header("base_link"), point: Point::from(scene.target) };
    // Until the node answers, keep the sensors coming (a best-effort sample may be lost).
    let warm_up = Instant::now() + Duration::from_secs(60);
    loop {
        assert!(Instant::now() < warm_up, "pps-ros2 never answered a click");
        info.publish(camera_info(&scene.calibration.intrinsics, header("camera_optical"))).unwrap();
        image.publish(image_message(&scene.image, header("camera_optical"))).unwrap();
        points.publish(cloud_message(&scene.cloud, header("base_link"))).unwrap();
        click.publish(the_click()).unwrap();
        if tokio::time::timeout(Duration::from_secs(2), goal.async_take()).await.is_ok() {
            break;
        }
    }
    let mut latencies = Vec::with_capacity(CLICKS);
    for _ in 0..CLICKS {
        let start = Instant::now();
        click.publish(the_click()).unwrap();
        tokio::time::timeout(Duration::from_secs(10), goal.async_take())
            .await
            .expect("the goal comes within 10 s")
            .expect("the goal is readable");
        latencies.push(start.elapsed().as_secs_f64() * 1e3);
    }
    let mut sorted = latencies.clone();
    sorted.sort_by(f64::total_cmp);
    println!("click to /goal_pose through DDS and pps-ros2: {}", summary(latencies));
    println!(
        "  beyond the chain's own time (transport, DDS, scheduling): {:.2} ms at the median",
        sorted[sorted.len() / 2] - chain_ms
    );
    let _ = node_process.kill();
    let _ = node_process.wait();
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` does not, and runs nothing here.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    if !netns::inside() {
        let output = netns::rerun_inside(&["--bench"]);
        print!("{}", String::from_utf8_lossy(&output.stdout));
        eprint!("{}", String::from_utf8_lossy(&output.stderr));
        assert!(output.status.success(), "the benchmark failed inside the namespace");
        return;
    }
    eprintln!("rendering the benchmark scene…");
    let scene = scene();
    println!(
        "scene: {}×{} image, {} points",
        scene.image.width,
        scene.image.height,
        scene.cloud.len()
    );
    let chain_ms = in_process(&scene);
    tokio::runtime::Runtime::new().unwrap().block_on(over_dds(&scene, chain_ms));
}
