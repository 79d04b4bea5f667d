//! The scene source itself: its ray caster against hand-computed hits, its laser's noise growing
//! with range and incidence, its mixed pixels and dropouts, the tag's colour in the camera
//! under bright and dim light, the ground truth, and the corpus's spread over issue 11's space.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pps_robot::perception::HsvThresholds;
use pps_scenes::camera::CameraModel;
use pps_scenes::caster::RayCaster;
use pps_scenes::corpus::Lighting;
use pps_scenes::devices::{DeviceKind, DeviceParameters};
use pps_scenes::geometry::{Ray, Shape};
use pps_scenes::laser::LaserModel;
use pps_scenes::lighting::{Lights, PointLight};
use pps_scenes::materials::{self, Material};
use pps_scenes::noise::NoiseSource;
use pps_scenes::scene::{Pose, Primitive, Scene};
use pps_scenes::{draw, generate};

fn dark() -> Lights {
    Lights { ambient: [0.0; 3], room: vec![], flash: None }
}

/// A wall facing the origin `distance` metres away, its normal turned `incidence` radians about z.
fn wall(distance: f64, incidence: f64) -> Primitive {
    let facing = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), incidence)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    Primitive::new(
        "wall",
        Shape::Rectangle { half_size: [3.0, 6.0] },
        Isometry3::from_parts(Translation3::new(distance, 0.0, 1.0), facing),
        materials::WALLS[0],
    )
}

#[test]
fn the_caster_meets_shapes_where_hand_geometry_says() {
    let scene = Scene {
        primitives: vec![
            // A cabinet front: a box 0.4 m deep whose face is at x = 1.5.
            Primitive::new(
                "box",
                Shape::Box { half_extents: [0.2, 0.3, 0.4] },
                Isometry3::translation(1.7, 0.0, 0.5),
                materials::FURNITURE[1],
            ),
            // A pole standing at (1.0, 0.6), radius 2 cm.
            Primitive::new(
                "pole",
                Shape::Cylinder { radius: 0.02, half_length: 0.75, capped: true },
                Isometry3::translation(1.0, 0.6, 0.75),
                materials::CHROME,
            ),
            // The floor.
            Primitive::new(
                "floor",
                Shape::Rectangle { half_size: [5.0, 5.0] },
                Isometry3::identity(),
                materials::FLOORS[0],
            ),
        ],
        lights: dark(),
    };
    let caster = RayCaster::new(&scene);
    let all = caster.all();
    let from = Point3::new(0.0, 0.0, 0.5);
    let hit = caster.cast(&Ray::new(from, Vector3::x()), &all, 10.0).unwrap();
    assert_eq!(hit.primitive, 0);
    assert!((hit.t - 1.5).abs() < 1e-9 && (hit.normal + Vector3::x()).norm() < 1e-9);
    // 45° down from 0.5 m: the floor at 0.5 m ahead, t = 0.5·√2.
    let hit = caster.cast(&Ray::new(from, Vector3::new(1.0, 0.0, -1.0)), &all, 10.0).unwrap();
    assert_eq!(hit.primitive, 2);
    assert!((hit.t - 0.5 * 2f64.sqrt()).abs() < 1e-9 && hit.normal.z > 0.999);
    // Toward the pole's axis: its surface 2 cm short of the axis.
    let to_pole = Vector3::new(1.0, 0.6, 0.0);
    let hit = caster.cast(&Ray::new(from, to_pole), &all, 10.0).unwrap();
    assert_eq!(hit.primitive, 1);
    assert!((hit.t - (to_pole.norm() - 0.02)).abs() < 1e-9, "{}", hit.t);
    // The box's top edge: a ray just over it reaches the floor far behind.
    let over = Vector3::new(1.5, 0.0, 0.4 + 0.001);
    let hit = caster.cast(&Ray::new(from, over), &all, 10.0);
    assert!(hit.is_none(), "above the box and the floor is below: nothing, got {hit:?}");
}

fn quiet_laser(bearing_half_span_deg: f64) -> LaserModel {
    LaserModel {
        head: Pose::at(Vector3::new(0.0, 0.0, 1.0)),
        axis_offset_m: 0.0,
        bearing_half_span_deg,
        beam_step_deg: 0.25,
        tilt_from_deg: -3.0,
        tilt_to_deg: 3.0,
        tilt_step_deg: 0.25,
        tilt_jitter_deg: 0.0,
        divergence_deg: 0.0,
        noise_scale: 1.0,
        dropout_rate: 0.0,
        min_range_m: 0.05,
        max_range_m: 20.0,
    }
}

/// σ of the measured ranges about the true ones, for a wall at `distance` turned by `incidence`.
fn range_spread(distance: f64, incidence: f64) -> (f64, usize) {
    let scene = Scene { primitives: vec![wall(distance, incidence)], lights: dark() };
    let caster = RayCaster::new(&scene);
    let laser = quiet_laser(3.0);
    let sweep = laser.scan(&caster, &mut NoiseSource::new(5, 1));
    let head = Point3::new(0.0, 0.0, 1.0);
    let errors: Vec<f64> = sweep
        .cloud
        .points
        .iter()
        .map(|p| {
            let p: Point3<f64> = p.cast();
            let ray = Ray::new(head, p - head);
            let truth = caster.cast(&ray, &caster.all(), 50.0).unwrap().t;
            (p - head).norm() - truth
        })
        .collect();
    let n = errors.len() as f64;
    let mean = errors.iter().sum::<f64>() / n;
    ((errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n).sqrt(), errors.len())
}

#[test]
fn the_range_noise_grows_with_range_and_with_incidence() {
    let laser = quiet_laser(3.0);
    let mut last = 0.0;
    for range in [0.3, 1.0, 2.0, 3.0] {
        let sigma = laser.range_sigma(range, 0.0);
        assert!(sigma > last && (0.002..=0.012).contains(&sigma), "{range} m: {sigma}");
        last = sigma;
    }
    let mut last = 0.0;
    for degrees in [0.0, 30.0, 60.0, 75.0] {
        let sigma = laser.range_sigma(1.0, f64::to_radians(degrees));
        assert!(sigma > last && sigma <= 0.012, "{degrees}°: {sigma}");
        last = sigma;
    }
    // And in the cloud itself.
    let (near, _) = range_spread(1.0, 0.0);
    let (far, _) = range_spread(3.0, 0.0);
    let (slanted, _) = range_spread(1.0, 65f64.to_radians());
    assert!((near - 0.0045).abs() < 0.0008, "1 m square on: σ {near}");
    assert!(far > 1.6 * near, "3 m: σ {far} against {near}");
    assert!(slanted > 1.5 * near, "65°: σ {slanted} against {near}");
}

#[test]
fn grazing_incidence_loses_returns() {
    let (_, square_on) = range_spread(1.5, 0.0);
    let (_, grazing) = range_spread(1.5, 80f64.to_radians());
    // At 80° the wall is still in every beam's way, but a tenth or more of the returns are lost.
    assert!(grazing < square_on * 9 / 10, "{grazing} of {square_on}");
}

#[test]
fn beams_straddling_a_depth_edge_come_back_between_the_surfaces() {
    // A board 10 cm before a wall, its edge across the scan.
    let board = Primitive::new(
        "board",
        Shape::Box { half_extents: [0.01, 0.5, 1.0] },
        Isometry3::translation(1.4, -0.5, 1.0),
        materials::FURNITURE[0],
    );
    let scene = Scene { primitives: vec![wall(1.5, 0.0), board], lights: dark() };
    let caster = RayCaster::new(&scene);
    let between = |laser: &LaserModel| {
        let sweep = laser.scan(&caster, &mut NoiseSource::new(9, 1));
        sweep.cloud.points.iter().filter(|p| p.x > 1.405 && p.x < 1.49).count()
    };
    let mut laser = quiet_laser(20.0);
    laser.noise_scale = 0.3;
    assert_eq!(between(&laser), 0, "a point beam never mixes");
    laser.divergence_deg = 0.4;
    let mixed = between(&laser);
    assert!(mixed > 5, "a wide footprint leaves a veil at the edge: {mixed} points");
}

#[test]
fn servo_jitter_shifts_whole_scan_lines() {
    // Looking down at the floor from 1 m: a line tilted off its commanded angle meets the floor
    // nearer or further, and the driver, placing the points at the commanded angle, lifts or
    // sinks the whole line.
    let floor = Primitive::new(
        "floor",
        Shape::Rectangle { half_size: [5.0, 5.0] },
        Isometry3::identity(),
        materials::FLOORS[1],
    );
    let scene = Scene { primitives: vec![floor], lights: dark() };
    let caster = RayCaster::new(&scene);
    let line_heights = |jitter: f64| {
        let mut laser = quiet_laser(5.0);
        (laser.tilt_from_deg, laser.tilt_to_deg) = (35.0, 45.0);
        laser.noise_scale = 0.0; // the 2 mm floor of σ
        laser.tilt_jitter_deg = jitter;
        let sweep = laser.scan(&caster, &mut NoiseSource::new(4, 1));
        let per_line = (2.0 * 5.0 / 0.25) as usize + 1;
        assert_eq!(sweep.cloud.len() % per_line, 0, "no dropouts on a bright floor");
        let means: Vec<f64> = sweep
            .cloud
            .points
            .chunks(per_line)
            .map(|line| line.iter().map(|p| f64::from(p.z)).sum::<f64>() / per_line as f64)
            .collect();
        (means.iter().map(|z| z * z).sum::<f64>() / means.len() as f64).sqrt()
    };
    let still = line_heights(0.0);
    let shaken = line_heights(0.2);
    // 0.2° at 40° down from 1 m moves the range ~6.5 mm and the line ~4 mm.
    assert!(still < 0.001, "without jitter the lines lie on the floor: {still}");
    assert!(shaken > 0.002 && shaken < 0.010, "with 0.2° of jitter: {shaken}");
}

/// A flash-lit wall 1 m ahead carrying a 30 cm square of `tag`, under `lighting`.
fn tag_scene(tag: Material, lighting: Lighting) -> Scene {
    let patch = Primitive::new(
        "patch",
        Shape::Box { half_extents: [0.004, 0.15, 0.15] },
        Isometry3::translation(0.996, 0.0, 1.2),
        tag,
    );
    let warm = [1.0, 0.78, 0.5];
    let (ambient, room) = match lighting {
        Lighting::Bright => (0.15, 3.0),
        Lighting::Dim => (0.005, 0.0),
    };
    Scene {
        primitives: vec![wall(1.0, 0.0), patch],
        lights: Lights {
            ambient: warm.map(|c| c * ambient),
            room: vec![PointLight {
                position: [0.6, -0.8, 2.5],
                intensity: warm.map(|c| c * room),
            }],
            flash: Some(PointLight { position: [0.0, 0.0, 1.24], intensity: [0.8; 3] }),
        },
    }
}

fn camera_at_one_metre(bias: f64, white_balance: [f64; 3]) -> CameraModel {
    // Level, looking along +x: optical z = x, optical x = −y, optical y = −z.
    let rotation =
        UnitQuaternion::from_basis_unchecked(&[-Vector3::y(), -Vector3::z(), Vector3::x()]);
    CameraModel {
        width: 640,
        height: 480,
        fx: 520.0,
        fy: 520.0,
        cx: 320.0,
        cy: 240.0,
        pose: Pose::from_isometry(&Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 1.2),
            rotation,
        )),
        exposure_bias_ev: bias,
        white_balance,
        vignetting: 0.9,
        // The noisiest sensor the corpus draws.
        read_noise: 0.002,
        shot_noise: 0.001,
    }
}

#[test]
fn the_tag_is_red_enough_in_bright_and_dim_light_with_the_flash() {
    let red = HsvThresholds::default();
    for tag in [materials::RED_TOWEL, materials::RED_FOAM, materials::RED_DYCEM] {
        for lighting in [Lighting::Bright, Lighting::Dim] {
            for (bias, balance) in [(-0.5, [0.95, 1.0, 1.05]), (0.5, [1.05, 1.0, 0.95])] {
                let scene = tag_scene(tag.scaled(0.85), lighting);
                let caster = RayCaster::new(&scene);
                let camera = camera_at_one_metre(bias, balance);
                let picture = camera.render(&scene, &caster, &mut NoiseSource::new(2, 3));
                // The tag covers ±78 px about the centre; look at its middle 60 × 60: its mean
                // colour is red, and noise flips few pixels (morphology mends those).
                let (mut passing, mut sum) = (0, [0u32; 3]);
                for y in 210..270 {
                    for x in 290..350 {
                        let px = picture.image.pixel(x, y);
                        passing += usize::from(red.contains(px));
                        (0..3).for_each(|c| sum[c] += u32::from(px[c]));
                    }
                }
                let mean = sum.map(|c| (c / 3600) as u8);
                assert!(
                    red.contains(mean) && passing >= 3600 * 95 / 100,
                    "{tag:?} {lighting:?} bias {bias}: mean {mean:?}, {passing} of 3600 pass"
                );
                assert!(!red.contains(picture.image.pixel(40, 240)), "the wall is not red");
            }
        }
    }
}

#[test]
fn nothing_but_the_red_things_is_red_under_any_light() {
    let red = HsvThresholds::default();
    let palettes: Vec<Material> = [
        &materials::WALLS[..],
        &materials::FURNITURE,
        &materials::FLOORS,
        &materials::CANS,
        &materials::PLASTICS,
        &materials::SHADES,
        &materials::CLUTTER,
        &[materials::CHROME, materials::BLACK_METAL],
    ]
    .concat();
    let lights = [[1.0, 0.78, 0.5], [1.0, 0.97, 0.92], [1.0, 0.98, 0.95]];
    for m in &palettes {
        for light in lights {
            for balance in [[1.05, 1.0, 0.95], [0.95, 1.0, 1.05]] {
                for exposure in [0.3, 0.6, 1.0, 1.6, 2.5] {
                    let rgb: [u8; 3] = std::array::from_fn(|c| {
                        pps_scenes::camera::linear_to_srgb8(
                            m.albedo[c] * light[c] * balance[c] * exposure,
                        )
                    });
                    assert!(!red.contains(rgb), "{m:?} under {light:?} reads red: {rgb:?}");
                }
            }
        }
    }
    for m in [materials::RED_BOOK, materials::RED_MUG, materials::RED_CUSHION] {
        let rgb: [u8; 3] =
            std::array::from_fn(|c| pps_scenes::camera::linear_to_srgb8(m.albedo[c] * 0.5));
        assert!(red.contains(rgb), "a distractor must look like a tag: {rgb:?}");
    }
}

#[test]
fn the_truth_is_where_the_tag_is() {
    for kind in DeviceKind::ALL {
        for seed in 0..20 {
            let drawn = draw(seed, Some(kind), 0);
            let truth = &drawn.truth;
            let caster = RayCaster::new(&drawn.scene);
            let eye = Point3::from(drawn.camera.pose.translation);
            let tag = Point3::from(truth.tag_center);
            // A ray from the camera toward the tag's centre meets the tag at or near it.
            let hit = caster.cast(&Ray::new(eye, tag - eye), &caster.all(), 10.0);
            let hit = hit.unwrap_or_else(|| panic!("{kind} {seed}: nothing toward the tag"));
            let reach = match drawn.parameters.device {
                DeviceParameters::FlipSwitch(s) => {
                    s.tube_radius_m.hypot(s.tube_length_m / 2.0) + 0.005
                }
                DeviceParameters::Lamp(l) => l.tube_radius_m + 0.005,
                _ => 0.012,
            };
            assert!(caster.material(hit.primitive).is_tag, "{kind} {seed}: the tag is hidden");
            let off = (hit.point - tag).norm();
            assert!(off <= reach, "{kind} {seed}: the tag's surface is {off} m from its centre");
            // The waypoint is 50 cm out along the horizontal normal, which faces the camera.
            let n = Vector3::from(truth.backing_normal);
            let out = Point3::from(truth.expected_waypoint) - tag;
            assert!((out.norm() - 0.5).abs() < 1e-9 && (out.normalize() - n).norm() < 1e-9);
            assert!(n.dot(&(eye - tag)) > 0.0, "{kind} {seed}: the normal faces the room");
            let error = Vector3::from(drawn.parameters.pointing_error_m);
            assert!(error.norm() <= 0.05);
            assert!((Point3::from(drawn.target) - tag - error).norm() < 1e-9);
        }
    }
}

#[test]
fn the_corpus_spans_the_space_of_issue_11() {
    let (mut angles, mut distances, mut pitches, mut heights) = (vec![], vec![], vec![], vec![]);
    let (mut fronts, mut proud, mut widths) = (vec![], vec![], vec![]);
    let (mut dim, mut near_red, mut sizes) = (0, 0, std::collections::BTreeSet::new());
    for kind in DeviceKind::ALL {
        for seed in 0..100 {
            let p = draw(seed, Some(kind), 0).parameters;
            angles.push(p.view_angle_deg);
            distances.push(p.distance_m);
            pitches.push(p.camera_pitch_deg);
            heights.push(p.camera_height_m);
            sizes.insert(p.image_size);
            dim += usize::from(p.lighting == Lighting::Dim);
            near_red += usize::from(p.distractor.is_some_and(|d| d.gap_m <= 0.3));
            if let DeviceParameters::Drawer(d) = p.device {
                fronts.push(d.front_width_m);
                proud.push(d.towel_proud_m);
                widths.push(d.towel_width_m / d.front_width_m);
            }
            let offset = Vector3::from(p.laser_offset_m).norm();
            assert!((0.05..=0.30).contains(&offset), "laser {offset} m from the camera");
            assert!((0.25..=0.5).contains(&p.beam_step_deg));
        }
    }
    let range = |v: &[f64]| {
        (
            v.iter().copied().fold(f64::INFINITY, f64::min),
            v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    let (lo, hi) = range(&angles);
    assert!(lo < -70.0 && hi > 70.0 && lo >= -75.0 && hi <= 75.0, "view angles {lo}..{hi}");
    let (lo, hi) = range(&distances);
    assert!(lo < 0.85 && hi > 1.55 && lo >= 0.8 && hi <= 1.6, "distances {lo}..{hi}");
    let (lo, hi) = range(&pitches);
    assert!(lo < 22.0 && hi > 43.0 && lo >= 20.0 && hi <= 45.0, "pitches {lo}..{hi}");
    let (lo, hi) = range(&heights);
    assert!(lo < 0.85 && hi > 1.35 && lo >= 0.8 && hi <= 1.4, "camera heights {lo}..{hi}");
    let (lo, hi) = range(&fronts);
    assert!(lo < 0.4 && hi > 1.1, "fronts {lo}..{hi}");
    let (lo, hi) = range(&proud);
    assert!(lo < 0.003 && hi > 0.027, "towels proud {lo}..{hi}");
    let (_, hi) = range(&widths);
    assert!(hi <= 0.5 + 1e-12 && hi > 0.45, "towel up to half the front, {hi}");
    assert!(dim > 100 && dim < 400, "{dim} of 500 dim");
    assert!(near_red > 50, "{near_red} scenes with a red thing within 30 cm of the tag");
    assert!(sizes.contains(&[640, 480]) && sizes.contains(&[1280, 960]));
}

#[test]
fn a_seed_always_gives_the_same_scene() {
    let a = generate(7, Some(DeviceKind::Rocker));
    let b = generate(7, Some(DeviceKind::Rocker));
    assert_eq!(a.image, b.image);
    assert_eq!(a.cloud, b.cloud);
    assert_eq!(a.drawn, b.drawn);
    let other = generate(8, Some(DeviceKind::Rocker));
    assert_ne!(a.drawn.parameters, other.drawn.parameters);
    let cloud = a.cloud.len();
    let [w, _] = a.drawn.parameters.image_size;
    // 60k points at 640 wide to 250k at 1280, give or take the draw's spread and the misses.
    let expected = 60_000.0 + 190_000.0 * (f64::from(w) - 640.0) / 640.0;
    assert!(
        (cloud as f64) > 0.75 * expected && (cloud as f64) < 1.25 * expected,
        "{cloud} points at {w} wide"
    );
    assert_eq!(a.calibration, a.drawn.camera.calibration());
}
