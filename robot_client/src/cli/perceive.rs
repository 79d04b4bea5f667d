//! `pps-robot perceive`: the tag, its backing plane and the approach waypoint from a recorded
//! image, cloud or aligned depth image, and camera calibration (DESIGN §6, §10).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use clap::{ArgGroup, Args};
use nalgebra::Point3;
use pps_schema::{ColorSegmentation, TagSize};
use serde::Serialize;

use crate::hal::PointCloud;
use crate::navigation::{
    ApproachParams, ApproachPlan, Clearance, plan_approach, plan_approach_on_depth,
};
use crate::perception::{
    DepthImage, DepthNoise, DepthRange, HsvThresholds, TagDetection, TagSighting,
};
use crate::picture::draw_overlay;
use crate::sensor_files::{read_camera_file, read_depth, read_ply, read_png_of_size, write_png};
use crate::timings::StepTimings;

#[derive(Debug, Args)]
#[command(group(ArgGroup::new("range_data").required(true).args(["cloud", "depth"])))]
pub struct PerceiveArgs {
    /// Colour image (PNG) taken by the calibrated camera.
    #[arg(long)]
    pub image: PathBuf,
    /// Laser point cloud (PLY, vertices x y z in the base frame, metres).
    #[arg(long)]
    pub cloud: Option<PathBuf>,
    /// Or the RGB-D camera's depth image aligned to --image: 16-bit greyscale PNG in
    /// millimetres or greyscale PFM in metres (0 or NaN: no depth; kept 0.1–10 m).
    #[arg(long)]
    pub depth: Option<PathBuf>,
    /// The depth camera's noise (σ) at 1 m, metres, that made --depth or --cloud; it grows with
    /// the square of the range. Default with --depth 0.0036 (a RealSense D435 at 848 pixels);
    /// with --cloud, a laser's few millimetres at any range.
    #[arg(long, value_name = "METRES", allow_hyphen_values = true, value_parser = parse_depth_noise)]
    pub depth_noise_at_1m: Option<DepthNoise>,
    /// Camera calibration JSON: width, height, fx, fy, cx, cy, base_from_camera.
    #[arg(long)]
    pub camera: PathBuf,
    /// The designated target X,Y,Z in the base frame, metres.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_target)]
    pub target: Point3<f64>,
    /// Tag colour HMIN,HMAX,SMIN,SMAX,VMIN,VMAX: hue in degrees (may wrap, 340,20), saturation
    /// and value 0..1. Default 340,20,0.6,1.0,0.15,1.0.
    #[arg(long, value_name = "HMIN,HMAX,SMIN,SMAX,VMIN,VMAX", allow_hyphen_values = true, value_parser = parse_hsv)]
    pub hsv: Option<HsvThresholds>,
    /// The home's largest tag as registered (`tag_size`), WIDTH,HEIGHT in metres: a red region
    /// reaching further than its half diagonal and 3 cm, or, as the camera sees it, wider than
    /// its narrower side or longer than its diagonal by three pixels, is never taken as a tag,
    /// though a piece of it a disc a little wider than the tag cannot reach may be. Default: a
    /// towel over a wide drawer's handle (60 × 35 cm), no bound on the width or length and no
    /// such piece.
    #[arg(long, value_name = "WIDTH,HEIGHT", allow_hyphen_values = true, value_parser = parse_largest_tag)]
    pub largest_tag: Option<TagSize>,
    /// Print one JSON document on stdout and nothing else.
    #[arg(long)]
    pub json: bool,
    /// Also draw the paper's Fig. 5 into the camera image and write it here as PNG: volume of
    /// interest cyan, tag red, backing plane dark green, waypoint and footprint yellow-green.
    #[arg(long, value_name = "PNG")]
    pub overlay: Option<PathBuf>,
}

fn parse_numbers(text: &str, count: usize, what: &str) -> Result<Vec<f64>, String> {
    let numbers: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>().map_err(|_| format!("`{}` is not a number", s.trim())))
        .collect::<Result<_, _>>()?;
    if numbers.len() != count {
        return Err(format!("{what} takes {count} comma-separated numbers, got {}", numbers.len()));
    }
    if let Some(bad) = numbers.iter().find(|v| !v.is_finite()) {
        return Err(format!("{bad} is not a finite number"));
    }
    Ok(numbers)
}

fn parse_target(text: &str) -> Result<Point3<f64>, String> {
    let v = parse_numbers(text, 3, "--target")?;
    Ok(Point3::new(v[0], v[1], v[2]))
}

fn parse_depth_noise(text: &str) -> Result<DepthNoise, String> {
    let sigma = parse_numbers(text, 1, "--depth-noise-at-1m")?[0];
    DepthNoise::stated_at_one_metre(sigma).map_err(|e| e.to_string())
}

fn parse_largest_tag(text: &str) -> Result<TagSize, String> {
    let v = parse_numbers(text, 2, "--largest-tag")?;
    if v.iter().any(|side| !(0.01..=1.0).contains(side)) {
        return Err(format!(
            "{},{} is not a tag's width and height: give each side in metres, from 0.01 to 1 \
             (a patch on a rocker switch is 0.05,0.08)",
            v[0], v[1]
        ));
    }
    Ok(TagSize { width: v[0], height: v[1] })
}

fn parse_hsv(text: &str) -> Result<HsvThresholds, String> {
    let v = parse_numbers(text, 6, "--hsv")?;
    HsvThresholds::new(&ColorSegmentation {
        hue_deg: [v[0], v[1]],
        saturation: [v[2], v[3]],
        value: [v[4], v[5]],
    })
    .map_err(|e| e.to_string())
}

/// The `--json` document.
#[derive(Debug, Serialize)]
pub struct PerceiveReport {
    pub tag: Option<TagJson>,
    /// What the tag search has to say in words: red regions divided because no tag is that
    /// large, or why none near the target was taken.
    pub tag_notes: Vec<String>,
    pub backing_plane: Option<PlaneJson>,
    pub waypoint: Option<WaypointJson>,
    pub load_ms: f64,
    pub timings_ms: StepTimings,
    /// Every plane found or tried that was not taken as the backing plane, and why.
    pub rejected_planes: Vec<RejectedPlaneJson>,
    /// The laser's noise across surfaces as measured in the cloud (standard deviation, metres;
    /// the median over the planes found, null when none was).
    pub laser_noise: Option<f64>,
}

#[derive(Debug, Serialize)]
pub struct RejectedPlaneJson {
    pub normal: [f64; 3],
    pub offset: f64,
    pub points: usize,
    pub why: String,
}

#[derive(Debug, Serialize)]
pub struct TagJson {
    pub centroid: [f64; 3],
    pub points: usize,
    /// Present only when another tag was about as near the target.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ambiguous_with: Option<Box<TagJson>>,
}

#[derive(Debug, Serialize)]
pub struct PlaneJson {
    pub normal: [f64; 3],
    pub offset: f64,
    pub points: usize,
}

#[derive(Debug, Serialize)]
pub struct WaypointJson {
    pub position: [f64; 3],
    pub yaw: f64,
    /// Whether the robot, arm extended, fits there without touching the cloud.
    pub clear: bool,
}

fn tag_json(tag: &TagDetection) -> TagJson {
    TagJson { centroid: tag.centroid.coords.into(), points: tag.points, ambiguous_with: None }
}

impl PerceiveReport {
    pub fn new(plan: &ApproachPlan, load_ms: f64) -> Self {
        let tag = plan.tag.as_ref().map(|sighting| match sighting {
            TagSighting::Found(tag) => tag_json(tag),
            TagSighting::Ambiguous { nearest, other } => {
                TagJson { ambiguous_with: Some(Box::new(tag_json(other))), ..tag_json(nearest) }
            }
        });
        Self {
            tag,
            tag_notes: plan.tag_notes.clone(),
            backing_plane: plan.backing_plane.as_ref().map(|p| PlaneJson {
                normal: p.normal.into(),
                offset: p.offset,
                points: p.points,
            }),
            waypoint: plan.waypoint.as_ref().map(|w| WaypointJson {
                position: w.position.coords.into(),
                yaw: w.yaw,
                clear: !matches!(plan.clearance, Some(Clearance::Blocked { .. })),
            }),
            load_ms,
            timings_ms: plan.timings.clone(),
            rejected_planes: plan
                .rejected_planes
                .iter()
                .map(|r| RejectedPlaneJson {
                    normal: r.normal.into(),
                    offset: r.offset,
                    points: r.points,
                    why: r.why.to_string(),
                })
                .collect(),
            laser_noise: plan.laser_noise(),
        }
    }
}

pub fn run(args: &PerceiveArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    // The calibration first: every image is checked against it before its pixels are decoded.
    let calibration = read_camera_file(&args.camera)?;
    let size = (calibration.intrinsics.width, calibration.intrinsics.height);
    let image = read_png_of_size(&args.image, size)?;
    let range_data = match (&args.cloud, &args.depth) {
        (Some(cloud), _) => RangeData::Cloud(read_ply(cloud)?),
        (None, Some(depth)) => RangeData::Depth(read_depth(depth, size)?),
        (None, None) => anyhow::bail!("give the range data as --cloud PLY or --depth IMAGE"),
    };
    let load_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut params = ApproachParams::default();
    let depth_image = matches!(range_data, RangeData::Depth(_));
    params.depth_noise = DepthNoise::stated_or_typical(args.depth_noise_at_1m, depth_image);
    if let Some(hsv) = args.hsv {
        params.tag.thresholds = hsv;
    }
    if let Some(largest) = args.largest_tag {
        params.tag = params.tag.for_home_tags([largest]);
    }
    // Turning depth into a cloud is a compute step, and the first; on a depth frame only the
    // pixels that can matter are turned into points.
    let (plan, range_summary) = match range_data {
        RangeData::Cloud(cloud) => {
            let plan = plan_approach(&image, &cloud, &calibration, &args.target, &params)
                .context("cannot run perception on these files")?;
            (plan, format!("cloud: {} points", cloud.len()))
        }
        RangeData::Depth(depth) => {
            let range = DepthRange::default();
            let plan =
                plan_approach_on_depth(&image, &depth, &calibration, &args.target, &range, &params)
                    .context("cannot run perception on these files")?;
            let frame = format!("depth: {}×{} pixels", depth.width(), depth.height());
            (plan, frame)
        }
    };
    let report = PerceiveReport::new(&plan, load_ms);
    if let Some(path) = &args.overlay {
        write_png(path, &draw_overlay(&image, &calibration, &plan, &params.footprint))?;
        eprintln!("wrote overlay to {}", path.display());
    }
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        print_summary(&report, &plan, &range_summary, args.largest_tag.is_some());
    }
    Ok(())
}

/// What a person trying `perceive` on their own frames can change when no tag was found:
/// `refused`, a red region near the target was seen and not taken; `sized`, the home's largest
/// tag was given.
fn no_tag_advice(refused: bool, sized: bool) -> &'static str {
    match (refused, sized) {
        (false, _) => {
            "nothing red near the target: check that --target lies on the tag (base frame, \
             metres) and that the tag's colour is within --hsv or its default"
        }
        (true, false) => {
            "a red region larger than any tag is nearest the target: give the home's largest \
             tag with --largest-tag WIDTH,HEIGHT (metres) to have it divided by the tag's size \
             as well"
        }
        (true, true) => {
            "the tag could not be told from the red thing nearest the target: a target on the \
             tag's middle, or the red thing moved away, may let it be found"
        }
    }
}

/// What the robot measured the scene's geometry with.
enum RangeData {
    Cloud(PointCloud),
    Depth(DepthImage),
}

fn print_summary(report: &PerceiveReport, plan: &ApproachPlan, range_summary: &str, sized: bool) {
    let f3 = |v: [f64; 3]| format!("({:.3}, {:.3}, {:.3})", v[0], v[1], v[2]);
    let noise =
        report.laser_noise.map_or("unknown".to_string(), |sigma| format!("{:.1} mm", sigma * 1e3));
    println!(
        "{range_summary}, {} points in the volume of interest, {} planes; laser noise \
         across them {noise}",
        plan.voi_points,
        plan.planes.len(),
    );
    match &report.tag {
        Some(tag) => {
            println!("tag: centroid {} m from {} points", f3(tag.centroid), tag.points);
            if let Some(other) = &tag.ambiguous_with {
                println!(
                    "  ambiguous: another tag at {} is about as near the target",
                    f3(other.centroid)
                );
            }
        }
        None => println!("tag: none found near the target"),
    }
    for note in &report.tag_notes {
        println!("  {note}");
    }
    if report.tag.is_none() {
        println!("  what to do: {}", no_tag_advice(!report.tag_notes.is_empty(), sized));
    }
    match &report.backing_plane {
        Some(p) => println!(
            "backing plane: normal {} toward the robot, offset {:.3} m, {} points",
            f3(p.normal),
            p.offset,
            p.points
        ),
        None => println!("backing plane: none qualified"),
    }
    for r in &report.rejected_planes {
        println!(
            "  not taken: plane with normal {}, offset {:.3} m, {} points: {}",
            f3(r.normal),
            r.offset,
            r.points,
            r.why
        );
    }
    match &report.waypoint {
        Some(w) => println!(
            "waypoint: {} m, yaw {:.1}°, {}",
            f3(w.position),
            w.yaw.to_degrees(),
            if w.clear { "clear" } else { "BLOCKED" }
        ),
        None => println!("waypoint: none"),
    }
    let steps: Vec<String> =
        report.timings_ms.steps().iter().map(|(n, ms)| format!("{n} {ms:.2}")).collect();
    println!(
        "load {:.1} ms; compute {:.2} ms: {}",
        report.load_ms,
        report.timings_ms.total_ms(),
        steps.join(", ")
    );
}
