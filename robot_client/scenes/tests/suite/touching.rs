//! A tag is a bounded thing (issue 34): where a plywood cabinet or a red plastic bin touches the
//! towel, the red region holding the tag is far larger than the tag, and perception must still
//! find the tag itself, with the factory colour thresholds. Every miss is printed with its seed
//! and the scene's parameters.
//!
//! `PPS_TOUCHING_SCENES` changes the number of scenes of each kind (24 by default).

use pps_robot::navigation::{ApproachParams, plan_approach};
use pps_scenes::judge;
use pps_scenes::touching::{Touching, touching_scene};

/// The share of scenes that must be right, per kind, as reached: every plywood scene, and 21
/// of 24 of the bin's (FINDINGS.md has the three it misses and why).
const REQUIRED_PLYWOOD: f64 = 1.0;
const REQUIRED_BIN: f64 = 0.875;

fn right_of(touching: Touching) -> (usize, usize) {
    let scenes: u64 =
        std::env::var("PPS_TOUCHING_SCENES").ok().and_then(|v| v.parse().ok()).unwrap_or(24);
    let outcomes: Vec<(bool, bool)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..2u64)
            .map(|w| {
                s.spawn(move || {
                    (w..scenes)
                        .step_by(2)
                        .map(|seed| {
                            let scene = touching_scene(seed, touching);
                            let plan = plan_approach(
                                &scene.image,
                                &scene.cloud,
                                &scene.calibration,
                                &scene.target,
                                &ApproachParams::default(),
                            )
                            .expect("perception runs");
                            let verdict = judge(scene.truth(), &plan);
                            // The same look with tags unbounded, as perception was before.
                            let mut unbounded = ApproachParams::default();
                            unbounded.tag.max_tag_radius = f64::INFINITY;
                            let before = plan_approach(
                                &scene.image,
                                &scene.cloud,
                                &scene.calibration,
                                &scene.target,
                                &unbounded,
                            )
                            .map(|plan| judge(scene.truth(), &plan).is_right())
                            .unwrap_or(false);
                            if !verdict.is_right() {
                                let points = plan.tag.as_ref().map(|t| t.nearest().points);
                                println!(
                                    "MISS {touching:?} seed {seed}: {} (tag of {points:?} points; \
                                     {} laser points on the towel) — {}; notes: {:?}",
                                    verdict.problems.join(", "),
                                    scene.visibility.tag_points,
                                    scene.parameters().summary(),
                                    plan.tag_notes,
                                );
                            }
                            (verdict.is_right(), before)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers.into_iter().flat_map(|w| w.join().expect("a worker panicked")).collect()
    });
    let before = outcomes.iter().filter(|(_, before)| *before).count();
    println!("{touching:?}: {before}/{} right with tags unbounded", outcomes.len());
    (outcomes.iter().filter(|(right, _)| *right).count(), outcomes.len())
}

fn assert_rate(touching: Touching, required: f64) {
    let (right, total) = right_of(touching);
    println!("{touching:?}: {right}/{total} right");
    assert!(
        right as f64 >= required * total as f64,
        "{touching:?}: only {right} of {total} scenes right"
    );
}

#[test]
fn a_tag_on_a_plywood_cabinet_is_found_apart_from_the_wood() {
    assert_rate(Touching::PlywoodCabinet, REQUIRED_PLYWOOD);
}

#[test]
fn a_tag_touched_by_a_red_bin_is_found_apart_from_the_bin() {
    assert_rate(Touching::RedBin, REQUIRED_BIN);
}
