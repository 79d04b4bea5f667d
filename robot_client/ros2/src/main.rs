//! `pps-ros2`: the PPS-tag node for ROS 2 robots (DESIGN §7).

use std::net::IpAddr;

use clap::Parser;
use pps_robot::cli::RegistryArgs;
use pps_robot::navigation::ApproachParams;
use pps_robot::perception::{DepthNoise, HsvThresholds};
use pps_robot::task::{ColourSource, TaskConfig};
use pps_ros2::dds::DdsSettings;
use pps_ros2::msg::visualization::MarkerLayout;
use pps_ros2::node::{NodeSettings, run};
use pps_ros2::topics::Topics;
use pps_schema::ColorSegmentation;

/// A ROS 2 node: the PPS-tag registry and the paper's perception for any ROS 2 robot.
#[derive(Debug, Parser)]
#[command(name = "pps-ros2", version, about)]
struct Cli {
    #[command(flatten)]
    registry: RegistryArgs,
    /// The robot's base frame: the cloud and clicks are in it, and the goal is given in it.
    #[arg(long, default_value = "base_link")]
    base_frame: String,
    /// Tag colour HMIN,HMAX,SMIN,SMAX,VMIN,VMAX: hue in degrees (may wrap, 340,20), saturation
    /// and value 0..1. Default: the colour the registry knows the home's tags to have (learned
    /// from confirmed reads, else their entries' colours), else 340,20,0.6,1.0,0.15,1.0.
    #[arg(long, value_name = "HMIN,HMAX,SMIN,SMAX,VMIN,VMAX", allow_hyphen_values = true, value_parser = parse_hsv)]
    hsv: Option<HsvThresholds>,
    /// The range sensor's depth noise (σ) at 1 m, metres; it grows with the square of the
    /// range. Default for depth images 0.0036 (a RealSense D435 at 848 pixels); for point
    /// clouds, a laser's few millimetres at any range.
    #[arg(long, value_name = "METRES", value_parser = parse_depth_noise)]
    depth_noise_at_1m: Option<DepthNoise>,
    /// A topic remap FROM:=TO, e.g. /camera/image_raw:=/head_camera/rgb/image_raw; repeatable.
    #[arg(long = "remap", value_name = "FROM:=TO")]
    remaps: Vec<String>,
    /// The only network interface DDS uses and announces, by its address (e.g. 127.0.0.1 for
    /// loopback); every interface when not given.
    #[arg(long, env = "PPS_DDS_INTERFACE", value_name = "ADDRESS")]
    dds_interface: Option<IpAddr>,
    /// The robot's ROS 2 distribution (humble, jazzy, ...), as its setup script sets
    /// `ROS_DISTRO`: Humble's RViz reads an older layout of the markers. Default jazzy.
    #[arg(long, env = "ROS_DISTRO", default_value = "jazzy")]
    ros_distro: String,
    /// Send trials without the picture of the click that led to them.
    #[arg(long)]
    no_picture: bool,
}

fn parse_hsv(text: &str) -> Result<HsvThresholds, String> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>().map_err(|_| format!("`{}` is not a number", s.trim())))
        .collect::<Result<_, _>>()?;
    let [h0, h1, s0, s1, v0, v1] = v[..] else {
        return Err(format!("--hsv takes 6 comma-separated numbers, got {}", v.len()));
    };
    HsvThresholds::new(&ColorSegmentation {
        hue_deg: [h0, h1],
        saturation: [s0, s1],
        value: [v0, v1],
    })
    .map_err(|e| e.to_string())
}

fn parse_depth_noise(text: &str) -> Result<DepthNoise, String> {
    let sigma: f64 =
        text.trim().parse().map_err(|_| format!("`{}` is not a number", text.trim()))?;
    DepthNoise::stated_at_one_metre(sigma).map_err(|e| e.to_string())
}

#[tokio::main]
async fn main() -> anyhow::Result<()> {
    // The node's own lines only: RustDDS logs through `log`, which is not forwarded here,
    // since it warns about every datagram it could not deliver to a peer that went away.
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env().unwrap_or_else(|_| "info".into()),
        )
        .init();
    let cli = Cli::parse();
    let topics = Topics::remapped(&cli.remaps).map_err(anyhow::Error::msg)?;
    let registry = cli.registry.connect()?;
    // Knowing the home's tags before the first read keeps the node answering offline.
    match registry.sync_entries().await {
        Ok(count) => tracing::info!("{count} tags known from the registry"),
        Err(e) => tracing::warn!("starting from the cached entries: {e}"),
    }
    let _watch = registry.watch_changes();
    let mut approach = ApproachParams::default();
    if let Some(hsv) = cli.hsv {
        approach.tag.thresholds = hsv;
    }
    let settings = NodeSettings {
        topics,
        base_frame: cli.base_frame.trim_start_matches('/').to_owned(),
        approach,
        depth_noise: cli.depth_noise_at_1m,
        rfid_margin_db: TaskConfig::default().rfid_margin_db,
        marker_layout: MarkerLayout::of_distro(&cli.ros_distro),
        picture: !cli.no_picture,
        colour: if cli.hsv.is_some() { ColourSource::AsGiven } else { ColourSource::KnownTags },
    };
    let dds = DdsSettings {
        domain_id: DdsSettings::domain_from_env().map_err(anyhow::Error::msg)?,
        interface: cli.dds_interface,
    };
    let context = dds.context().map_err(anyhow::Error::msg)?;
    run(context, registry, settings, async {
        let _ = tokio::signal::ctrl_c().await;
        tracing::info!("stopping");
    })
    .await
}
