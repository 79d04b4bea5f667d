//! The laser: range noise growing with range and incidence, returns lost at grazing
//! incidence, mixed pixels at depth edges, and servo jitter.

use nalgebra::{Isometry3, Point3, Vector3};
use pps_scenes::caster::RayCaster;
use pps_scenes::geometry::{Ray, Shape};
use pps_scenes::laser::LaserModel;
use pps_scenes::materials;
use pps_scenes::noise::NoiseSource;
use pps_scenes::scene::{Pose, Primitive, Scene};

use super::{dark, wall};

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
