//! Perception (paper §III-B) on rendered scenes: the robot 1.5 m from each device, at the
//! paper's four start directions, seeded.

use nalgebra::{Point3, Vector3};
use pps_robot::perception::{Mask, TagSearchParams, TagSighting, locate_tag, segment_color};
use pps_robot::sim::{
    CaptureSettings, DeviceKind, Room, RoomOptions, SceneCapture, StartDirection, capture_scene,
};
use pps_robot::timings::StepTimings;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn locate(scene: &SceneCapture, target: &Point3<f64>) -> Option<TagSighting> {
    locate_tag(
        &scene.image,
        &scene.cloud,
        &scene.calibration,
        target,
        &TagSearchParams::default(),
        &mut StepTimings::default(),
    )
    .expect("image and calibration agree")
}

/// The pixel a base-frame point projects to.
fn pixel_of(scene: &SceneCapture, p: &Point3<f64>) -> (usize, usize) {
    let in_camera = scene.calibration.base_from_camera.inverse() * p;
    let uv = scene.calibration.intrinsics.project(&in_camera).expect("in front of the camera");
    (uv.x as usize, uv.y as usize)
}

#[test]
fn tag_centroid_within_2_cm_from_the_paper_starts() {
    for device in DeviceKind::ALL {
        for direction in StartDirection::PAPER {
            for seed in 0..5 {
                let scene = capture_scene(
                    Room::paper(),
                    device,
                    direction,
                    1.5,
                    seed,
                    &CaptureSettings::small(),
                );
                let sighting = locate(&scene, &scene.target);
                let Some(TagSighting::Found(tag)) = sighting else {
                    panic!("{device:?} from {direction:?}, seed {seed}: {sighting:?}");
                };
                let error = (tag.centroid - scene.tag_truth).norm();
                assert!(
                    error < 0.02,
                    "{device:?} from {direction:?}, seed {seed}: {:.1} cm off",
                    error * 100.0
                );
            }
        }
    }
}

#[test]
fn segmentation_and_morphology_keep_the_tag_and_drop_wood_specks() {
    let scene = capture_scene(
        Room::paper(),
        DeviceKind::Drawer,
        StartDirection::Front,
        1.5,
        3,
        &CaptureSettings::small(),
    );
    let params = TagSearchParams::default();
    let raw = segment_color(&scene.image, &params.thresholds);
    let clean = raw.fill_holes().close(params.close_radius_px).open(params.open_radius_px);
    let (u, v) = pixel_of(&scene, &scene.tag_truth);
    assert!(clean.get(u, v), "the towel's centre is red");
    // The bookshelf's grain and the sensor noise leave lone red pixels; opening leaves none.
    let lone = |m: &Mask| {
        let set = |x: usize, y: usize| x < m.width() && y < m.height() && m.get(x, y);
        (1..m.height() - 1)
            .flat_map(|y| (1..m.width() - 1).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                set(x, y)
                    && !(y - 1..=y + 1)
                        .any(|yy| (x - 1..=x + 1).any(|xx| (xx, yy) != (x, y) && set(xx, yy)))
            })
            .count()
    };
    assert!(lone(&raw) > 0, "the wood and the noise tempt the thresholds");
    assert_eq!(lone(&clean), 0, "morphology leaves no lone red pixel");
}

#[test]
fn no_tag_when_nothing_is_red() {
    let room = || Room::new(RoomOptions { red_tags: false, ..RoomOptions::default() });
    let mut raw_red_pixels = 0;
    for device in DeviceKind::ALL {
        for direction in [StartDirection::FarLeft, StartDirection::Front] {
            let scene = capture_scene(room(), device, direction, 1.5, 7, &CaptureSettings::small());
            raw_red_pixels +=
                segment_color(&scene.image, &TagSearchParams::default().thresholds).count();
            assert_eq!(locate(&scene, &scene.target), None, "{device:?} from {direction:?}");
        }
    }
    assert!(raw_red_pixels > 0, "wood grain gives the segmentation something to be fooled by");
}

#[test]
fn tags_30_cm_apart_are_told_apart_or_reported_ambiguous() {
    // The flip switch and the rocker switch 30 cm apart on one wall.
    let room = || Room::new(RoomOptions { switch_spacing: 0.3, ..RoomOptions::default() });
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let (mut right, mut ambiguous) = (0, 0);
    for (device, direction) in [
        (DeviceKind::LightSwitch, StartDirection::Front),
        (DeviceKind::AdaLightSwitch, StartDirection::Left),
        (DeviceKind::LightSwitch, StartDirection::FarRight),
    ] {
        let scene = capture_scene(room(), device, direction, 1.5, 11, &CaptureSettings::small());
        let tags: Vec<Point3<f64>> = [DeviceKind::LightSwitch, DeviceKind::AdaLightSwitch]
            .iter()
            .map(|k| scene.all_tags.iter().find(|(kind, _)| kind == k).expect("both switches").1)
            .collect();
        for meant in [0, 1] {
            // Targets up to 12 cm off the tag the person meant: right or ambiguous, never the other.
            for _ in 0..50 {
                let offset = Vector3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                let target = tags[meant] + offset.normalize() * rng.random_range(0.0..0.12);
                match locate(&scene, &target) {
                    Some(TagSighting::Found(tag)) => {
                        assert!(
                            (tag.centroid - tags[meant]).norm() < 0.03,
                            "{device:?} {direction:?}: took the other tag"
                        );
                        right += 1;
                    }
                    Some(TagSighting::Ambiguous { nearest, other }) => {
                        let both = [nearest.centroid, other.centroid];
                        assert!(
                            both.iter().any(|c| (c - tags[0]).norm() < 0.03)
                                && both.iter().any(|c| (c - tags[1]).norm() < 0.03)
                        );
                        ambiguous += 1;
                    }
                    None => panic!("{device:?} {direction:?}: no tag near {target:?}"),
                }
            }
        }
        // Halfway between them nobody can tell.
        let midway = nalgebra::center(&tags[0], &tags[1]);
        assert!(matches!(locate(&scene, &midway), Some(TagSighting::Ambiguous { .. })));
    }
    assert!(
        right > ambiguous,
        "most targets near a tag identify it ({right} right, {ambiguous} ambiguous)"
    );
}
