//! A simulated robot on ROS 2, for trying pps-ros2 without a robot: the simulator's camera
//! image, camera info, static camera transform and laser cloud, the operator's click on the
//! device's tag, and an inventory round of the fingers held up to it; it prints what the node
//! answers. Run it, like every DDS process, inside a loopback-only network namespace (README).
//!
//! This is the only place where ROS 2 meets the simulator: the node never does.

use std::time::Duration;

use clap::Parser;
use pps_robot::hal::RfidReader;
use pps_robot::sim::{
    CaptureSettings, DeviceKind, Room, SimRobot, StartDirection, capture_scene, start_pose,
};
use pps_ros2::camera::camera_info;
use pps_ros2::cloud::cloud_message;
use pps_ros2::dds::DdsSettings;
use pps_ros2::image::image_message;
use pps_ros2::msg::builtin::{Header, Time};
use pps_ros2::msg::geometry::{Point, PointStamped, PoseStamped, Transform, TransformStamped};
use pps_ros2::msg::pps::{TagEntry, TagRead, TagReads};
use pps_ros2::msg::sensor::{CameraInfo, Image, PointCloud2};
use pps_ros2::msg::tf::TfMessage;
use pps_ros2::qos;
use pps_ros2::topics::{advertise, subscribe};
use ros2_client::{NodeName, NodeOptions, Publisher, Subscription};

/// Publishes a simulated robot's sensors over ROS 2 and prints what pps-ros2 answers.
#[derive(Debug, Parser)]
struct Args {
    /// The device the robot stands by: light switch, ada light switch, lamp, drawer, trash can.
    #[arg(long, default_value = "light switch")]
    device: String,
    /// Where it starts, seen from the tag: far-left, left, front, right, far-right.
    #[arg(long, default_value = "left")]
    direction: String,
    /// How far from the tag, metres.
    #[arg(long, default_value_t = 1.5)]
    distance: f64,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Seconds between clicks and inventory rounds (the sensors stream twice as often).
    #[arg(long, default_value_t = 4.0)]
    every: f64,
    /// Stop after this many clicks (and one more period for the node's answers); without it,
    /// run until Ctrl-C.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    clicks: Option<u64>,
    /// The only interface DDS uses, e.g. 127.0.0.1 inside the namespace.
    #[arg(long, env = "PPS_DDS_INTERFACE")]
    dds_interface: Option<std::net::IpAddr>,
}

fn header(frame: &str) -> Header {
    Header { stamp: Time::now(), frame_id: frame.into() }
}

#[tokio::main]
async fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let device = DeviceKind::parse(&args.device)
        .ok_or_else(|| anyhow::anyhow!("no device `{}` in the simulated room", args.device))?;
    let direction = StartDirection::parse(&args.direction)
        .ok_or_else(|| anyhow::anyhow!("no start direction `{}`", args.direction))?;
    eprintln!(
        "rendering the {} from {} m, {}…",
        device.type_name(),
        args.distance,
        direction.name()
    );
    let scene = capture_scene(
        Room::paper(),
        device,
        direction,
        args.distance,
        args.seed,
        &CaptureSettings::full(),
    );
    let t = scene.tag_truth;
    eprintln!(
        "{}×{} image, {} points; the tag truly at ({:.3}, {:.3}, {:.3}) in base_link",
        scene.image.width,
        scene.image.height,
        scene.cloud.len(),
        t.x,
        t.y,
        t.z
    );
    // The fingers held up to the tag, as the robot is once it has driven there.
    let room = Room::paper();
    let close = SimRobot::new(
        room.clone(),
        start_pose(room.device(device), StartDirection::Front, 0.45),
        args.seed,
    );
    close.state().body.carriage_height = room.device(device).tag_center.z;

    let dds = DdsSettings {
        domain_id: DdsSettings::domain_from_env().map_err(anyhow::Error::msg)?,
        interface: args.dds_interface,
    };
    let context = dds.context().map_err(anyhow::Error::msg)?;
    let mut node = context
        .new_node(NodeName::new("/", "pps_sim_robot")?, NodeOptions::new().enable_rosout(false))
        .map_err(|e| anyhow::anyhow!("cannot create the node: {e:?}"))?;
    let image: Publisher<Image> = advertise(&mut node, "/camera/image_raw", qos::command())?;
    let info: Publisher<CameraInfo> = advertise(&mut node, "/camera/camera_info", qos::command())?;
    let points: Publisher<PointCloud2> = advertise(&mut node, "/points", qos::command())?;
    let tf_static: Publisher<TfMessage> = advertise(&mut node, "/tf_static", qos::latched())?;
    let click: Publisher<PointStamped> = advertise(&mut node, "/clicked_point", qos::command())?;
    let rfid: Publisher<TagReads> = advertise(&mut node, "/pps/rfid", qos::command())?;
    let goal: Subscription<PoseStamped> = subscribe(&mut node, "/goal_pose", qos::command())?;
    let tag: Subscription<PoseStamped> = subscribe(&mut node, "/pps/tag_pose", qos::command())?;
    let entry: Subscription<TagEntry> = subscribe(&mut node, "/pps/entry", qos::command())?;
    let spinner = node.spinner().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    tokio::spawn(spinner.spin());

    let camera_frame = "camera_optical";
    tf_static.publish(TfMessage {
        transforms: vec![TransformStamped {
            header: header("base_link"),
            child_frame_id: camera_frame.into(),
            transform: Transform::from_isometry(&scene.calibration.base_from_camera),
        }],
    })?;
    tokio::spawn(async move {
        loop {
            match tag.async_take().await {
                Ok((p, _)) => println!(
                    "tag pose: ({:.3}, {:.3}, {:.3})",
                    p.pose.position.x, p.pose.position.y, p.pose.position.z
                ),
                Err(e) => eprintln!("tag pose unreadable: {e}"),
            }
        }
    });
    tokio::spawn(async move {
        loop {
            match goal.async_take().await {
                Ok((p, _)) => {
                    let q = p.pose.orientation;
                    let yaw = 2.0 * q.z.atan2(q.w);
                    println!(
                        "goal: ({:.3}, {:.3}) facing {:.1}°",
                        p.pose.position.x,
                        p.pose.position.y,
                        yaw.to_degrees()
                    );
                }
                Err(e) => eprintln!("goal unreadable: {e}"),
            }
        }
    });
    tokio::spawn(async move {
        loop {
            match entry.async_take().await {
                Ok((e, _)) if e.error.is_empty() => println!(
                    "entry: {} revision {}{}",
                    e.epc,
                    e.revision,
                    if e.ambiguous { " (ambiguous)" } else { "" }
                ),
                Ok((e, _)) => println!("entry: {}", e.error),
                Err(e) => eprintln!("entry unreadable: {e}"),
            }
        }
    });

    match args.clicks {
        Some(n) => eprintln!("publishing; stops after {n} clicks, or press Ctrl-C"),
        None => eprintln!("publishing until you press Ctrl-C (--clicks N stops after N clicks)"),
    }
    let stream_every = Duration::from_secs_f64(args.every / 2.0);
    let mut tick = 0u64;
    let mut clicked = 0u64;
    loop {
        info.publish(camera_info(&scene.calibration.intrinsics, header(camera_frame)))?;
        image.publish(image_message(&scene.image, header(camera_frame)))?;
        points.publish(cloud_message(&scene.cloud, header("base_link")))?;
        if tick % 2 == 1 {
            click.publish(PointStamped {
                header: header("base_link"),
                point: Point::from(scene.target),
            })?;
            let reads = close.inventory().map_err(|e| anyhow::anyhow!("{e}"))?;
            rfid.publish(TagReads {
                stamp: Time::now(),
                reads: reads
                    .iter()
                    .map(|r| TagRead {
                        epc: r.epc.as_hex().to_owned(),
                        rssi_dbm: r.rssi_dbm,
                        antenna: r.antenna.0,
                    })
                    .collect(),
            })?;
            clicked += 1;
            if args.clicks == Some(clicked) {
                // One more period, so the node's answers to the last click are printed.
                #[allow(clippy::disallowed_methods, reason = "the simulated robot's pace")]
                tokio::time::sleep(Duration::from_secs_f64(args.every)).await;
                eprintln!("sent {clicked} clicks; stopping");
                return Ok(());
            }
        }
        tick += 1;
        #[allow(clippy::disallowed_methods, reason = "the simulated robot's pace")]
        tokio::time::sleep(stream_every).await;
    }
}
