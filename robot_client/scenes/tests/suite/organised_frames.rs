//! The approach on an RGB-D frame converts only the pixels that can matter
//! (`plan_approach_on_depth`), and must answer exactly as the whole frame's cloud does: the same
//! tag, backing plane, waypoint and clearance, on dense frames with holes and flying pixels,
//! wood and red things touching the tag.

use pps_robot::navigation::{ApproachParams, plan_approach, plan_approach_on_depth};
use pps_robot::perception::DepthRange;
use pps_scenes::{DeviceKind, RgbdVariants, generate_rgbd};

#[test]
fn the_windowed_frame_gives_the_whole_frames_answer() {
    let params = ApproachParams::default();
    for seed in 0..3 {
        for kind in DeviceKind::ALL {
            let scene = generate_rgbd(seed, Some(kind), RgbdVariants::HOMES);
            let depth = scene.depth_image().expect("an RGB-D scene has depth");
            let whole = plan_approach(
                &scene.image,
                &scene.cloud,
                &scene.calibration,
                &scene.target,
                &params,
            )
            .unwrap();
            let windowed = plan_approach_on_depth(
                &scene.image,
                &depth,
                &scene.calibration,
                &scene.target,
                &DepthRange::default(),
                &params,
            )
            .unwrap();
            let case = format!("{kind} seed {seed}: {}", scene.parameters().summary());
            // The tag's points come in the order its voxels were visited, which the cloud's
            // length moves; the tag is the same points.
            let tag = |plan: &pps_robot::navigation::ApproachPlan| {
                plan.tag.as_ref().map(|t| {
                    let t = t.nearest();
                    let mut members: Vec<[u32; 3]> =
                        t.members.iter().map(|p| [p.x, p.y, p.z].map(f32::to_bits)).collect();
                    members.sort_unstable();
                    (t.centroid, t.points, t.voxels, t.radius.to_bits(), members)
                })
            };
            assert_eq!(tag(&windowed), tag(&whole), "{case}");
            assert_eq!(
                windowed.tag.as_ref().map(|t| t.is_ambiguous()),
                whole.tag.as_ref().map(|t| t.is_ambiguous()),
                "{case}"
            );
            assert_eq!(windowed.voi_points, whole.voi_points, "{case}");
            assert_eq!(windowed.backing_plane, whole.backing_plane, "{case}");
            assert_eq!(windowed.waypoint, whole.waypoint, "{case}");
            assert_eq!(windowed.clearance, whole.clearance, "{case}");
        }
    }
}
