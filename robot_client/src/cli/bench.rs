//! `pps-robot bench-perception`: times each step of perception and navigation geometry, and the
//! whole chain, on a fixed benchmark scene: a 1280×960 image and a ~200 000-point tilting-laser
//! cloud of a wall with a drawer cabinet and its towel tag, seen from 1.5 m, 22.5° off its normal.
//!
//! Run it optimised: `cargo run --release -p pps-robot -- bench-perception`
//! (`--iterations N` repeats, `--export DIR` also writes the scene as image.png, cloud.ply,
//! camera.json and scene.json, for other tools or `pps-robot perceive`).

use std::path::PathBuf;

use anyhow::ensure;
use clap::Args;

use crate::navigation::{ApproachParams, plan_approach};
use crate::sim::{CaptureSettings, DeviceKind, Room, StartDirection, capture_scene};

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// How many times to run the chain; the report gives the median and the fastest run.
    #[arg(long, default_value_t = 30)]
    pub iterations: usize,
    /// Also write the benchmark scene into this directory.
    #[arg(long)]
    pub export: Option<PathBuf>,
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    ensure!(args.iterations > 0, "--iterations must be at least 1");
    tracing::info!("rendering the benchmark scene (1280×960 image, tilting-laser sweep)...");
    let scene = capture_scene(
        Room::paper(),
        DeviceKind::Drawer,
        StartDirection::Left,
        1.5,
        1,
        &CaptureSettings::full(),
    );
    if let Some(dir) = &args.export {
        scene.write(dir)?;
        tracing::info!("wrote the scene to {}", dir.display());
    }
    let params = ApproachParams::default();
    let mut runs = Vec::with_capacity(args.iterations);
    for _ in 0..args.iterations {
        runs.push(plan_approach(
            &scene.image,
            &scene.cloud,
            &scene.calibration,
            &scene.target,
            &params,
        )?);
    }
    let last = runs.last().expect("at least one run");
    let found = last.tag.as_ref().map(|t| (t.nearest().centroid - scene.tag_truth).norm());
    println!(
        "scene: {}×{} image, {} laser points, {} in the volume of interest, {} planes; tag {}",
        scene.image.width,
        scene.image.height,
        scene.cloud.len(),
        last.voi_points,
        last.planes.len(),
        found.map_or("not found".to_string(), |e| format!("found {:.1} cm from truth", e * 100.0))
    );
    println!("{:<20} {:>10} {:>10}", "step", "median ms", "min ms");
    for (name, _) in last.timings.steps() {
        let mut times: Vec<f64> = runs.iter().filter_map(|r| r.timings.get(name)).collect();
        println!(
            "{:<20} {:>10.3} {:>10.3}",
            name,
            median(&mut times),
            times.iter().copied().fold(f64::INFINITY, f64::min)
        );
    }
    let mut totals: Vec<f64> = runs.iter().map(|r| r.timings.total_ms()).collect();
    println!(
        "{:<20} {:>10.3} {:>10.3}",
        "whole chain",
        median(&mut totals),
        totals.iter().copied().fold(f64::INFINITY, f64::min)
    );
    Ok(())
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}
