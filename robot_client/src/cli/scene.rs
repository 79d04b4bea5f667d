//! `pps-robot scene`: export a simulated scene to try `perceive` on.

use std::path::PathBuf;

use clap::Args;

use super::parse::{parse_device, parse_direction};

use crate::sim::{AlignedDepth, CaptureSettings, DeviceKind, Room, StartDirection, capture_scene};

#[derive(Debug, Args)]
pub struct SceneArgs {
    /// light-switch, ada-light-switch, lamp, drawer or trash-can.
    #[arg(long, value_parser = parse_device)]
    pub device: DeviceKind,
    /// Where the robot stands, as seen by a person facing the device: far-left, left, front,
    /// right or far-right (the paper's starts are far-left, left, right, far-right).
    #[arg(long = "from", default_value = "front", value_parser = parse_direction)]
    pub from: StartDirection,
    /// Distance from the tag, metres.
    #[arg(long, default_value_t = 1.5)]
    pub distance: f64,
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// 320×240 and a cropped scan instead of 1280×960 and ~200 000 points.
    #[arg(long)]
    pub small: bool,
    /// Directory to write image.png, cloud.ply, camera.json and scene.json into.
    #[arg(long)]
    pub out: PathBuf,
    /// Also write what an RGB-D camera aligned to the colour camera would give: depth.png
    /// (16-bit, millimetres), depth.pfm (metres) and depth.ply (the points of the same rays).
    #[arg(long)]
    pub depth: bool,
}

pub fn run(args: &SceneArgs) -> anyhow::Result<()> {
    let settings = if args.small { CaptureSettings::small() } else { CaptureSettings::full() };
    let capture =
        capture_scene(Room::paper(), args.device, args.from, args.distance, args.seed, &settings);
    capture.write(&args.out)?;
    let dir = args.out.display();
    tracing::info!(
        "wrote {dir}/image.png ({}×{}), {dir}/cloud.ply ({} points), {dir}/camera.json, {dir}/scene.json",
        capture.image.width,
        capture.image.height,
        capture.cloud.len()
    );
    if args.depth {
        let depth = AlignedDepth::of(&capture, &Room::paper());
        depth.write(&args.out)?;
        tracing::info!(
            "wrote {dir}/depth.png, {dir}/depth.pfm and {dir}/depth.ply ({} points)",
            depth.cloud.len()
        );
    }
    println!(
        "pps-robot perceive --image {dir}/image.png --cloud {dir}/cloud.ply --camera {dir}/camera.json --target {}",
        capture.target_arg()
    );
    Ok(())
}
