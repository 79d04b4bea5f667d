//! Issue 11's bar for perception, on scenes it was not tuned to: over the independent corpus,
//! every device kind has at least 99 % of its scenes right (tag centroid within 4 cm, backing
//! normal within 15°, waypoint within 10 cm), with `ApproachParams::default()` and the range
//! sensor's noise model (the laser's, or the RGB-D camera's from its datasheet). Every miss is
//! printed with its seed, kind and drawn parameters; `pps-scenes write --seed N --kind K` writes
//! that scene for `pps-robot perceive`.
//!
//! The same bar holds on what RGB-D cameras give (issue 34): dense organised clouds from a
//! stereo or structured-light depth sensor with its own noise and holes, at 0.5–5 m, under warm
//! and cool light without a flash. `pps-scenes write --rgbd` writes such a scene (`--wood` or
//! `--homes` for the variants with wood, or with wood and red things touching the tag).
//!
//! What the robot knows of the home's tags matters where red things touch them: with every tag's
//! size registered, a red region larger than the home's largest tag is divided or refused.
//!
//! Each variant is one test per device kind. `PPS_SCENES_PER_KIND` changes the number of scenes
//! per kind (100 by default; 40 for the RGB-D frames to 5 m, whose scenes are the largest, and
//! for the variants not yet held to the bar, which are ignored with their reasons).

use nalgebra::Point3;
use pps_robot::navigation::{ApproachParams, plan_approach};
use pps_scenes::{
    DeviceKind, GeneratedScene, RgbdVariants, Verdict, generate, generate_rgbd, judge,
};

const REQUIRED_RATE: f64 = 0.99;

struct Outcome {
    kind: DeviceKind,
    seed: u64,
    verdict: Result<Verdict, String>,
    summary: String,
    render_ms: f64,
}

/// What the robot knows of the home's tags before it reads one.
#[derive(Clone, Copy)]
enum TagSizes {
    /// Nothing: a tag may be as large as a towel.
    Unregistered,
    /// Every tag's size is registered, and the scene's tag is the home's largest.
    Registered,
}

fn run(
    kind: DeviceKind,
    seed: u64,
    source: fn(u64, DeviceKind) -> GeneratedScene,
    sizes: TagSizes,
) -> Outcome {
    let scene = source(seed, kind);
    let mut params =
        ApproachParams { depth_noise: scene.depth_noise(), ..ApproachParams::default() };
    if let TagSizes::Registered = sizes {
        params.tag = params.tag.for_home_tags([scene.truth().registered_size()]);
    }
    let verdict =
        plan_approach(&scene.image, &scene.cloud, &scene.calibration, &scene.target, &params)
            .map(|plan| judge(scene.truth(), &plan))
            .map_err(|e| e.to_string());
    let v = scene.visibility;
    // How far the laser's own returns on the tag average from its centre: their density bias
    // (nearer parts are sampled more densely) and any part hidden from the laser.
    let bias = v.tag_points_centroid.map_or(f64::NAN, |c| {
        (Point3::from(c) - Point3::from(scene.truth().tag_center)).norm() * 100.0
    });
    let summary = format!(
        "{}; tag {} px, {} laser points averaging {bias:.1} cm from its centre; backing surface {} points near the tag; cloud {}",
        scene.parameters().summary(),
        v.tag_pixels,
        v.tag_points,
        v.backing_points,
        v.cloud_points
    );
    Outcome { kind, seed, verdict, summary, render_ms: scene.render_ms }
}

/// One test per device kind, so that the test runner spreads a variant's scenes over the cores
/// (each of these tests renders and perceives its scenes on one).
macro_rules! per_kind {
    ($(#[$attribute:meta])* $variant:ident, $per_kind:expr, $source:expr) => {
        per_kind!($(#[$attribute])* $variant, $per_kind, $source, TagSizes::Unregistered);
    };
    ($(#[$attribute:meta])* $variant:ident, $per_kind:expr, $source:expr, $sizes:expr) => {
        mod $variant {
            use super::*;

            $(#[$attribute])*
            #[test]
            fn flip_switch() {
                holds_the_bar(DeviceKind::FlipSwitch, $per_kind, $source, $sizes);
            }

            $(#[$attribute])*
            #[test]
            fn rocker() {
                holds_the_bar(DeviceKind::Rocker, $per_kind, $source, $sizes);
            }

            $(#[$attribute])*
            #[test]
            fn lamp() {
                holds_the_bar(DeviceKind::Lamp, $per_kind, $source, $sizes);
            }

            $(#[$attribute])*
            #[test]
            fn drawer() {
                holds_the_bar(DeviceKind::Drawer, $per_kind, $source, $sizes);
            }

            $(#[$attribute])*
            #[test]
            fn trash_can() {
                holds_the_bar(DeviceKind::TrashCan, $per_kind, $source, $sizes);
            }
        }
    };
}

per_kind!(perception_is_right_on_the_independent_corpus, 100, |seed, kind| generate(
    seed,
    Some(kind)
));

per_kind!(perception_is_right_on_dense_rgbd_frames_within_2_5_m, 100, |seed, kind| {
    generate_rgbd(seed, Some(kind), RgbdVariants::NEAR)
});

per_kind!(perception_is_right_on_dense_rgbd_frames_to_5_m, 40, |seed, kind| {
    generate_rgbd(seed, Some(kind), RgbdVariants::PLAIN)
});

// Wood behind and around the tag as the real captures of issue 34 had it (a plywood wall at
// 3.5-4.8 m), nothing red touching, sizes unknown.
per_kind!(perception_is_right_on_dense_rgbd_frames_with_wood_to_5_m, 40, |seed, kind| {
    generate_rgbd(seed, Some(kind), RgbdVariants::WOOD)
});

per_kind!(
    #[ignore = "not yet 99 % per kind: 33, 36, 34, 35 and 36 of 40 (flip switch, rocker, lamp, \
                drawer, trash can); with tag sizes unknown, a red thing touching a small tag \
                makes a region no larger than a towel, and one of the tag's own colour in the \
                picture stays joined to it (26 misses, each the tag 5-16 cm off); figures in \
                FINDINGS.md"]
    perception_is_right_with_wood_and_red_things_touching_the_tag,
    40,
    |seed, kind| {
        let near_homes = RgbdVariants { farthest_m: 2.5, ..RgbdVariants::HOMES };
        generate_rgbd(seed, Some(kind), near_homes)
    }
);

per_kind!(
    #[ignore = "not yet 99 % per kind: 39, 40, 38, 40 and 40 of 40 (flip switch, rocker, lamp, \
                drawer, trash can); 2 of the 3 misses are refusals in words (a foam tube behind \
                or beside a red thing of its colour), 1 takes a strip of fabric beside a lamp's \
                tube, 11 cm off; figures in FINDINGS.md"]
    perception_is_right_with_red_things_touching_tags_of_registered_size,
    40,
    |seed, kind| {
        let near_homes = RgbdVariants { farthest_m: 2.5, ..RgbdVariants::HOMES };
        generate_rgbd(seed, Some(kind), near_homes)
    },
    TagSizes::Registered
);

fn holds_the_bar(
    kind: DeviceKind,
    default_per_kind: u64,
    source: fn(u64, DeviceKind) -> GeneratedScene,
    sizes: TagSizes,
) {
    let per_kind: u64 = std::env::var("PPS_SCENES_PER_KIND")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default_per_kind);
    let outcomes: Vec<Outcome> = (0..per_kind).map(|seed| run(kind, seed, source, sizes)).collect();
    let mut right = 0;
    for o in &outcomes {
        match &o.verdict {
            Ok(v) if v.is_right() => right += 1,
            Ok(v) => println!(
                "MISS seed {} {}: {} — {}",
                o.seed,
                o.kind,
                v.problems.join(", "),
                o.summary
            ),
            Err(e) => {
                println!("MISS seed {} {}: perception failed: {e} — {}", o.seed, o.kind, o.summary)
            }
        }
    }
    let mut render: Vec<f64> = outcomes.iter().map(|o| o.render_ms).collect();
    render.sort_by(f64::total_cmp);
    println!(
        "rendering: {:.0} ms median, {:.0} ms p95 a scene",
        render[render.len() / 2],
        render[render.len() * 95 / 100]
    );
    let rate = right as f64 / outcomes.len() as f64;
    println!("{kind}: {right}/{} right ({:.1} %)", outcomes.len(), rate * 100.0);
    assert!(
        rate >= REQUIRED_RATE,
        "{kind}: {:.1} % right, below {:.0} %",
        rate * 100.0,
        REQUIRED_RATE * 100.0
    );
}
