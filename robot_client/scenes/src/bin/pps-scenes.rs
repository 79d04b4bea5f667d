//! `pps-scenes`: write one scene of the independent corpus to files `pps-robot perceive` reads,
//! or benchmark the approach over the corpus.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::{Parser, Subcommand};
use pps_robot::navigation::{ApproachParams, ApproachPlan, plan_approach, plan_approach_on_depth};
use pps_robot::perception::{DepthRange, cloud_from_depth};
use pps_robot::sensor_files::{
    PlyFormat, write_camera_file, write_depth_png, write_ply, write_png,
};
use pps_scenes::{DeviceKind, GeneratedScene, RgbdVariants, generate, generate_rgbd, judge};

#[derive(Debug, Parser)]
#[command(name = "pps-scenes", about = "An independent scene source for the robot's perception")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Render one scene and write image.png, cloud.ply, camera.json, truth.json and scene.json.
    Write {
        #[arg(long)]
        seed: u64,
        /// flip_switch, rocker, lamp, drawer or trash_can; the seed's own kind when left out.
        #[arg(long, value_parser = parse_kind)]
        kind: Option<DeviceKind>,
        /// As an RGB-D camera sees it at 0.5–5 m; depth.png, 16-bit millimetres aligned to
        /// image.png, is written too.
        #[arg(long)]
        rgbd: bool,
        /// With --rgbd: wood in the furniture and red things touching the tag as well.
        #[arg(long, requires = "rgbd")]
        homes: bool,
        /// With --rgbd: wood in the furniture and some walls, nothing red touching the tag.
        #[arg(long, requires = "rgbd", conflicts_with = "homes")]
        wood: bool,
        /// With --rgbd: the farthest the camera stands from the tag, metres (the corpus's
        /// variants "within 2.5 m" draw their scenes with 2.5).
        #[arg(long, requires = "rgbd", default_value_t = 5.0, value_parser = parse_farthest)]
        farthest: f64,
        #[arg(long)]
        out: PathBuf,
    },
    /// Write the scenes `bench` runs, each into its own directory `OUT/NNN`, for a peer
    /// implementation to be timed on the very same scenes.
    WriteCorpus {
        #[arg(long, default_value_t = 100)]
        scenes: u64,
        /// The RGB-D scenes `bench --rgbd` runs, each with its depth.png.
        #[arg(long)]
        rgbd: bool,
        /// With --rgbd: the scenes `bench --rgbd --homes` runs.
        #[arg(long, requires = "rgbd")]
        homes: bool,
        #[arg(long)]
        out: PathBuf,
    },
    /// Print the home-materials table: each material's hue and saturation under warm, neutral
    /// and cool light, with the white balance fixed for daylight or correcting the cast.
    Materials,
    /// Run the approach over the corpus and print the median and p95 of every step.
    Bench {
        /// Scenes to run, the device kinds in turn (seed i / 5 of kind i % 5, as the corpus test).
        #[arg(long, default_value_t = 100)]
        scenes: u64,
        /// Also write each scene's time to this CSV file (scene, cloud_points, voi_points,
        /// chain_ms), for comparing scene by scene with a peer.
        #[arg(long)]
        per_scene: Option<PathBuf>,
        /// Also write each scene's answers to this file, a line a scene, every number to the
        /// last bit: two builds that answer alike write the same file.
        #[arg(long)]
        answers: Option<PathBuf>,
        /// On the RGB-D scenes (dense depth frames at 0.5–5 m), through the organised path, each
        /// with its sensor's noise model as the corpus test gives it.
        #[arg(long)]
        rgbd: bool,
        /// With --rgbd: wood in the furniture and red things touching the tag as well.
        #[arg(long, requires = "rgbd")]
        homes: bool,
        /// With --rgbd: turn the whole frame into a cloud and run the laser's path on it, for
        /// comparing with the organised path.
        #[arg(long, requires = "rgbd")]
        whole_frame: bool,
    },
    /// How wrong the depth noise model may be: the RGB-D scenes to 5 m keep their sensor's true
    /// noise while perception is given its model scaled, or the laser's; prints a Markdown table
    /// of the scenes right per kind and every miss.
    Sensitivity {
        /// Scenes per device kind (seeds 0..N, as the corpus test draws them).
        #[arg(long, default_value_t = 40)]
        per_kind: u64,
        /// Factors for the model's growth with range (σ at 1 m); the laser's model is run too.
        #[arg(long, value_delimiter = ',', default_values_t = [1.0, 0.5, 2.0, 4.0])]
        scales: Vec<f64>,
        /// Wood in the furniture and red things touching the tag as well.
        #[arg(long)]
        homes: bool,
    },
}

/// The RGB-D variant to run: the plain frames to 5 m, or with the homes' wood and red things.
fn rgbd_variants(homes: bool) -> RgbdVariants {
    if homes { RgbdVariants::HOMES } else { RgbdVariants::PLAIN }
}

fn parse_farthest(text: &str) -> Result<f64, String> {
    let metres: f64 = text.parse().map_err(|_| format!("`{text}` is not a number of metres"))?;
    if (0.6..=5.0).contains(&metres) {
        Ok(metres)
    } else {
        Err(format!("{metres} m is outside the RGB-D scenes' ranges; give 0.6 to 5 m"))
    }
}

fn parse_kind(text: &str) -> Result<DeviceKind, String> {
    DeviceKind::parse(text).ok_or_else(|| {
        let names: Vec<&str> = DeviceKind::ALL.iter().map(|k| k.name()).collect();
        format!("`{text}` is not a device kind; one of {}", names.join(", "))
    })
}

fn main() -> anyhow::Result<()> {
    // The benchmark runs the chain on this thread: it works beside the pool, not waiting on it.
    pps_robot::cores::work_on_this_thread();
    match Cli::parse().command {
        Command::Write { seed, kind, rgbd, homes, wood, farthest, out } => {
            let drawn = if wood { RgbdVariants::WOOD } else { rgbd_variants(homes) };
            let variants = RgbdVariants { farthest_m: farthest, ..drawn };
            write(seed, kind, rgbd.then_some(variants), &out)
        }
        Command::WriteCorpus { scenes, rgbd, homes, out } => (0..scenes).try_for_each(|i| {
            let (seed, kind) = corpus_scene(i);
            let variants = rgbd.then(|| rgbd_variants(homes));
            write(seed, Some(kind), variants, &out.join(format!("{i:03}")))
        }),
        Command::Bench { scenes, per_scene, answers, rgbd, homes, whole_frame } => {
            let files = BenchFiles { per_scene: per_scene.as_deref(), answers: answers.as_deref() };
            bench(scenes, files, rgbd.then(|| rgbd_variants(homes)), whole_frame)
        }
        Command::Sensitivity { per_kind, scales, homes } => {
            sensitivity(per_kind, &scales, rgbd_variants(homes));
            Ok(())
        }
        Command::Materials => {
            print_materials();
            Ok(())
        }
    }
}

fn write(
    seed: u64,
    kind: Option<DeviceKind>,
    rgbd: Option<RgbdVariants>,
    out: &Path,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let scene = match rgbd {
        Some(variants) => generate_rgbd(seed, kind, variants),
        None => generate(seed, kind),
    };
    if let Some(mm) = &scene.depth_mm {
        let size = (scene.image.width, scene.image.height);
        write_depth_png(&out.join("depth.png"), size, mm)?;
    }
    let image = out.join("image.png");
    let cloud = out.join("cloud.ply");
    let camera = out.join("camera.json");
    write_png(&image, &scene.image)?;
    write_ply(&cloud, &scene.cloud, PlyFormat::BinaryLittleEndian)?;
    write_camera_file(&camera, &scene.calibration)?;
    let truth = serde_json::json!({
        "target": scene.drawn.target,
        "truth": scene.drawn.truth,
        "parameters": scene.drawn.parameters,
        "visibility": scene.visibility,
    });
    std::fs::write(out.join("truth.json"), serde_json::to_string_pretty(&truth)? + "\n")?;
    // The range sensor's noise model, σ(z) = floor + growth·z², as the corpus test gives it to
    // perception: a peer sizes its smoothing and tolerances by the same.
    let noise = scene.depth_noise();
    let described = serde_json::json!({
        "scene": scene.drawn.scene,
        "camera": scene.drawn.camera,
        "laser": scene.drawn.laser,
        "depth_noise": { "floor": noise.floor, "growth": noise.growth },
    });
    std::fs::write(out.join("scene.json"), serde_json::to_string_pretty(&described)? + "\n")?;
    let [x, y, z] = scene.drawn.target;
    eprintln!(
        "{} seed {seed}: {} (rendered in {:.0} ms)",
        scene.truth().kind,
        scene.parameters().summary(),
        scene.render_ms
    );
    println!(
        "pps-robot perceive --image {} --cloud {} --camera {} --target {x:.4},{y:.4},{z:.4}",
        image.display(),
        cloud.display(),
        camera.display()
    );
    Ok(())
}

/// The `i`-th scene of the benchmark: the device kinds in turn, seed `i / 5` of kind `i % 5`,
/// as the corpus test draws them.
fn corpus_scene(i: u64) -> (u64, DeviceKind) {
    let kinds = DeviceKind::ALL.len() as u64;
    (i / kinds, DeviceKind::ALL[(i % kinds) as usize])
}

/// The value below which `q` of the sorted `values` lie.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// What the benchmark writes beside its table: each scene's time, each scene's answers.
#[derive(Debug, Clone, Copy)]
struct BenchFiles<'a> {
    per_scene: Option<&'a Path>,
    answers: Option<&'a Path>,
}

/// `path` created for writing, or `None` when no path was given.
fn created(path: Option<&Path>) -> anyhow::Result<Option<BufWriter<File>>> {
    let Some(path) = path else { return Ok(None) };
    let file = File::create(path).with_context(|| format!("creating {}", path.display()))?;
    Ok(Some(BufWriter::new(file)))
}

/// One scene's answers on a line, every number in Rust's shortest form that reads back to the
/// same bits: the tag, the planes, the backing plane, the waypoint and its clearance.
fn answers_line(i: u64, plan: &ApproachPlan) -> String {
    let tag = plan.tag.as_ref().map(|t| {
        let t = t.nearest();
        (t.centroid, t.points, t.voxels)
    });
    let planes: Vec<_> =
        plan.planes.iter().map(|p| (p.plane.normal, p.plane.offset, p.inliers.len())).collect();
    format!(
        "{i:03} tag {tag:?} surface {} planes {planes:?} backing {:?} waypoint {:?} clearance {:?}",
        plan.surface_points.len(),
        plan.backing_plane,
        plan.waypoint,
        plan.clearance
    )
}

fn bench(
    scenes: u64,
    files: BenchFiles,
    rgbd: Option<RgbdVariants>,
    whole_frame: bool,
) -> anyhow::Result<()> {
    let mut steps: Vec<(&'static str, Vec<f64>)> = Vec::new();
    let (mut totals, mut renders) = (Vec::new(), Vec::new());
    let mut right = 0;
    // Opened first, so that a path that cannot be written fails before the run, not after it.
    let mut table = created(files.per_scene)?;
    let mut answers = created(files.answers)?;
    if let Some(table) = &mut table {
        writeln!(table, "scene,cloud_points,voi_points,chain_ms")?;
    }
    for i in 0..scenes {
        let (seed, kind) = corpus_scene(i);
        let scene: GeneratedScene = match rgbd {
            Some(variants) => generate_rgbd(seed, Some(kind), variants),
            None => generate(seed, Some(kind)),
        };
        renders.push(scene.render_ms);
        // As the corpus test runs it: with the range sensor's own noise model, so that a depth
        // camera's frame is smoothed along its rays and judged by tolerances from its noise.
        let params =
            ApproachParams { depth_noise: scene.depth_noise(), ..ApproachParams::default() };
        let plan = match scene.depth_image() {
            Some(depth) if whole_frame => {
                let start = std::time::Instant::now();
                let range = DepthRange::default();
                let cloud = cloud_from_depth(&depth, &scene.calibration, &range)?;
                let ms = start.elapsed().as_secs_f64() * 1e3;
                plan_approach(&scene.image, &cloud, &scene.calibration, &scene.target, &params)
                    .ok()
                    .map(|mut plan| {
                        plan.timings.add("depth_to_cloud", ms);
                        plan
                    })
            }
            Some(depth) => plan_approach_on_depth(
                &scene.image,
                &depth,
                &scene.calibration,
                &scene.target,
                &DepthRange::default(),
                &params,
            )
            .ok(),
            None => plan_approach(
                &scene.image,
                &scene.cloud,
                &scene.calibration,
                &scene.target,
                &params,
            )
            .ok(),
        };
        let Some(plan) = plan else {
            if let Some(answers) = &mut answers {
                writeln!(answers, "{i:03} no plan")?;
            }
            continue;
        };
        if let Some(answers) = &mut answers {
            writeln!(answers, "{}", answers_line(i, &plan))?;
        }
        right += usize::from(judge(scene.truth(), &plan).is_right());
        let total = plan.timings.total_ms();
        totals.push(total);
        if let Some(table) = &mut table {
            writeln!(table, "{i:03},{},{},{total:.4}", scene.cloud.len(), plan.voi_points)?;
        }
        for &(name, ms) in plan.timings.steps() {
            match steps.iter_mut().find(|(n, _)| *n == name) {
                Some((_, v)) => v.push(ms),
                None => steps.push((name, vec![ms])),
            }
        }
    }
    println!("{:<20} {:>9} {:>9}", "step (ms)", "median", "p95");
    for (name, mut v) in steps.into_iter().chain([("whole chain", totals)]) {
        v.sort_by(f64::total_cmp);
        println!("{name:<20} {:>9.2} {:>9.2}", quantile(&v, 0.5), quantile(&v, 0.95));
    }
    renders.sort_by(f64::total_cmp);
    println!(
        "{scenes} scenes, {right} right; rendering a scene took {:.0} ms median, {:.0} ms p95",
        quantile(&renders, 0.5),
        quantile(&renders, 0.95)
    );
    for file in [table, answers].into_iter().flatten() {
        file.into_inner().map_err(|e| e.into_error())?;
    }
    Ok(())
}

/// Runs the model-mismatch measurement and prints its table, then each miss.
fn sensitivity(per_kind: u64, scales: &[f64], variants: RgbdVariants) {
    use pps_scenes::sensitivity::{GivenModel, measure};
    let models: Vec<GivenModel> =
        scales.iter().map(|&s| GivenModel::Scaled(s)).chain([GivenModel::Laser]).collect();
    let start = std::time::Instant::now();
    let result = measure(per_kind, variants, &models);
    println!("{}", result.table());
    println!(
        "{per_kind} scenes a kind, each perceived with {} models, in {:.0} s",
        models.len(),
        start.elapsed().as_secs_f64()
    );
    for miss in &result.misses {
        println!(
            "MISS {} seed {} {}: {} — {}",
            miss.model.label(),
            miss.seed,
            miss.kind,
            miss.problems,
            miss.scene
        );
    }
}

/// The home-materials table in Markdown, hue° / saturation in each cell.
fn print_materials() {
    use pps_scenes::home_materials::{HOME_MATERIALS, Illuminant, WhiteBalance, rendered_hsv};
    let lightings: Vec<(Illuminant, WhiteBalance)> = Illuminant::ALL
        .into_iter()
        .map(|i| (i, WhiteBalance::Daylight))
        .chain([(Illuminant::Cool6500, WhiteBalance::Corrected)])
        .collect();
    let mut header = String::from("| material | group |");
    for (i, b) in &lightings {
        match b {
            WhiteBalance::Daylight => header += &format!(" {} K, daylight balance |", i.kelvin()),
            WhiteBalance::Corrected => header += " any light, corrected |",
        }
    }
    println!("{header}");
    println!("|---|---|{}", "---|".repeat(lightings.len()));
    for m in &HOME_MATERIALS {
        let cells: Vec<String> = lightings
            .iter()
            .map(|&(i, b)| {
                let [h, s, _] = rendered_hsv(m, i, b, 0.4);
                format!("{h:.1}° / {s:.2}")
            })
            .collect();
        println!("| {} | {:?} | {} |", m.name, m.group, cells.join(" | "));
    }
}
