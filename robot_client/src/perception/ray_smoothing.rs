//! Smoothing a depth camera's points along their rays, where its noise outgrows what surfaces
//! can be told apart by.
//!
//! A stereo or structured-light camera knows where each pixel looks exactly and only how far
//! along that ray roughly: at 4–5 m its depths scatter by 5–13 cm, more than the depth of a
//! drawer front's recess or the towel on it, and a plane search sees fog. But its frame is
//! dense: a surface fills hundreds of neighbouring pixels. On a plane the inverse depth is an
//! affine function of the pixel (`1/z = a + b·u + c·v`), so fitting that function over a block
//! of `w × w` pixels and moving each point along its own ray onto the fit averages the noise of
//! the block's points while keeping their directions: σ falls by about `w/√3`. Points further
//! from the fit than the noise allows (another surface in the block, a flying pixel) keep their
//! depth. The tag's colour and the rest of a block are fitted apart, as a joint bilateral
//! filter would: a foam tube 20 cm before a wall is within the noise of the wall at 4 m, and
//! must not be pulled onto it. A laser's noise needs no such help: the window is one pixel and
//! nothing moves.

use nalgebra::{Matrix3, Point3, Vector3};
use rustc_hash::FxHashMap;

use super::depth_noise::DepthNoise;
use super::hsv::HsvThresholds;
use super::organised_cloud::OrganisedCloud;
use crate::hal::{CameraCalibration, ColorImage};

/// Fewest points a block needs for its fit to average anything.
const MIN_BLOCK_POINTS: usize = 6;

/// Mean squared spread of a block's pixels across a line (pixels²) below which they lie on that
/// one row or column: `n` points on two rows spread by at least `(n − 1)/n²`, over 1/600 for the
/// largest block (24 × 24 pixels); the rounding of a pixel found again by projecting a point of
/// single precision, by about 1e-10.
const ONE_LINE_SPREAD: f64 = 1e-4;

/// How far from a block's fit a point may lie and still be on the block's surface, in standard
/// deviations of the depth there.
const SURFACE_SIGMAS: f64 = 3.0;

/// What the smoothing works with: the picture the tag's colour is read from, the camera, the box
/// around the target (base frame, from `min` to `max`) whose points it moves, the blocks' side
/// in pixels (`window`), and the depth's noise.
#[derive(Debug, Clone, Copy)]
pub struct RaySmoothing<'a> {
    pub image: &'a ColorImage,
    pub tag: &'a HsvThresholds,
    pub calibration: &'a CameraCalibration,
    pub min: Point3<f64>,
    pub max: Point3<f64>,
    pub window: u32,
    pub noise: &'a DepthNoise,
}

impl RaySmoothing<'_> {
    /// `points` (base frame, a depth camera's: one a pixel) with those inside the box moved
    /// along their camera rays onto the surface each `window × window`-pixel block of theirs
    /// shows, the points whose pixel in `image` has the tag's colour (`tag`) and the others each
    /// onto their own. Points outside the box, behind the camera, or off their block's surface
    /// are returned as they came, in the same order. Each point's pixel is found by projecting
    /// it; [`Self::of_organised`] reads it where the depth image's conversion left it.
    pub fn of_points(&self, points: &[Point3<f32>]) -> Vec<Point3<f32>> {
        let Self { image, tag, calibration, min, max, window, noise } = *self;
        let mut out = points.to_vec();
        if !fits_a_block(window) {
            return out;
        }
        let camera_from_base = calibration.base_from_camera.inverse();
        let k = &calibration.intrinsics;
        let w = f64::from(window);
        // Each point in the box, in camera coordinates with its pixel, and the block it falls in,
        // numbered as first met. A row of the frame crosses a block in `window` neighbouring
        // points, so most points are in the block of the point before them and need no lookup.
        let mut rays: Vec<RayPoint> = Vec::new();
        let mut block_of: Vec<u32> = Vec::new();
        // The keys are one frame's pixel blocks, chosen by nobody: SipHash's defence against chosen
        // keys buys nothing here and cost the step about 8 % of its time.
        let mut numbers: FxHashMap<(i64, i64, bool), u32> = FxHashMap::default();
        let mut last: Option<((i64, i64, bool), u32)> = None;
        for (i, p) in points.iter().enumerate() {
            let p = p.cast::<f64>();
            if !inside(&p, &min, &max) {
                continue;
            }
            let q = camera_from_base * p;
            if q.z <= 1e-6 {
                continue;
            }
            let (u, v) = (k.fx * q.x / q.z + k.cx, k.fy * q.y / q.z + k.cy);
            let in_image =
                u >= 0.0 && v >= 0.0 && u < f64::from(image.width) && v < f64::from(image.height);
            let tag_coloured = in_image && tag.contains(image.pixel(u as u32, v as u32));
            let key = ((u / w).floor() as i64, (v / w).floor() as i64, tag_coloured);
            let number = match last {
                Some((last_key, number)) if last_key == key => number,
                _ => {
                    let next = numbers.len() as u32;
                    let number = *numbers.entry(key).or_insert(next);
                    last = Some((key, number));
                    number
                }
            };
            rays.push(RayPoint::new(i, u, v, q.z, noise));
            block_of.push(number);
        }
        let camera = calibration.base_from_camera.translation.vector;
        smooth_blocks(&rays, &block_of, numbers.len(), noise, |m, depth| {
            out[m.index] = moved_along_ray(&points[m.index], &camera, depth / m.z);
        });
        out
    }

    /// [`Self::of_points`] on a depth image's own cloud, in place: each point's pixel and depth
    /// are the ones it was made from and the blocks are the image's `window × window` tiles. The
    /// same points are smoothed onto the same fits, to within the rounding of a pixel found
    /// again from a point of single precision.
    pub fn of_organised(&self, cloud: &mut OrganisedCloud<'_>) {
        let Self { image, tag, calibration, min, max, window, noise } = *self;
        if !fits_a_block(window) {
            return;
        }
        // The tiles the cloud's pixels fall in, a pair each: the tag's colour and the rest.
        let pixels = cloud.window();
        let (first_column, first_row) = (pixels.columns[0] / window, pixels.rows[0] / window);
        let columns = (pixels.columns[1].div_ceil(window)).saturating_sub(first_column) as usize;
        let rows = (pixels.rows[1].div_ceil(window)).saturating_sub(first_row) as usize;
        let mut rays: Vec<RayPoint> = Vec::new();
        let mut block_of: Vec<u32> = Vec::new();
        let points = &cloud.cloud().points;
        cloud.for_each_pixel(|i, u, v, z| {
            if !inside(&points[i].cast::<f64>(), &min, &max) {
                return;
            }
            let tag_coloured =
                u < image.width && v < image.height && tag.contains(image.pixel(u, v));
            let tile =
                (v / window - first_row) as usize * columns + (u / window - first_column) as usize;
            block_of.push((tile * 2 + usize::from(tag_coloured)) as u32);
            // The ray through pixel u is the one through u + 0.5 (as the conversion made it).
            rays.push(RayPoint::new(
                i,
                f64::from(u) + 0.5,
                f64::from(v) + 0.5,
                f64::from(z),
                noise,
            ));
        });
        let camera = calibration.base_from_camera.translation.vector;
        let points = cloud.points_mut();
        smooth_blocks(&rays, &block_of, rows * columns * 2, noise, |m, depth| {
            points[m.index] = moved_along_ray(&points[m.index], &camera, depth / m.z);
        });
    }
}

/// A depth camera gives one point a pixel, so a block holds at most `window²` points: below the
/// fewest a fit needs, no block would be fitted and nothing would move (a D435 at 1 m).
fn fits_a_block(window: u32) -> bool {
    window * window >= MIN_BLOCK_POINTS as u32
}

fn inside(p: &Point3<f64>, min: &Point3<f64>, max: &Point3<f64>) -> bool {
    (0..3).all(|a| p[a] >= min[a] && p[a] <= max[a])
}

/// `p` moved along the ray from the camera at `camera` (base frame) through it, its distance
/// from the camera scaled by `scale`.
fn moved_along_ray(p: &Point3<f32>, camera: &Vector3<f64>, scale: f64) -> Point3<f32> {
    let p = p.cast::<f64>();
    Point3::from(camera + (p.coords - camera) * scale).cast()
}

/// Fits each block of `rays` (block `block_of[i]` for ray `i`, `blocks` of them) and hands every
/// point on its block's surface to `moved(point, depth)` with the depth the fit gives it.
fn smooth_blocks(
    rays: &[RayPoint],
    block_of: &[u32],
    blocks: usize,
    noise: &DepthNoise,
    mut moved: impl FnMut(&RayPoint, f64),
) {
    // The blocks' points side by side, each block's in the cloud's order (a counting sort).
    let mut start = vec![0usize; blocks + 1];
    for &b in block_of {
        start[b as usize + 1] += 1;
    }
    for b in 0..blocks {
        start[b + 1] += start[b];
    }
    let mut next = start.clone();
    let mut grouped = rays.to_vec();
    for (ray, &b) in rays.iter().zip(block_of) {
        grouped[next[b as usize]] = *ray;
        next[b as usize] += 1;
    }
    let mut scratch = Scratch::default();
    for members in start.windows(2).map(|r| &grouped[r[0]..r[1]]) {
        if members.len() < MIN_BLOCK_POINTS {
            continue;
        }
        let Some(fit) = surface_of(members, noise, &mut scratch) else { continue };
        for m in members {
            let inverse = fit.inverse_depth(m.u, m.v);
            if inverse <= 0.0 || !fit.holds(m) {
                continue;
            }
            moved(m, 1.0 / inverse);
        }
    }
}

/// Room the blocks' fits reuse, one block after another.
#[derive(Default)]
struct Scratch {
    depths: Vec<f64>,
    on: Vec<(f64, f64, f64)>,
    /// Whether each of the block's points is among those the fit is made to.
    kept: Vec<bool>,
}

/// A point of the cloud by its pixel (`u`, `v`, continuous image coordinates) and its depth
/// along the optical axis (`z`, metres), and how far from a fit along its ray it may lie and
/// still be on the fit's surface (`band`, metres).
#[derive(Debug, Clone, Copy)]
struct RayPoint {
    index: usize,
    u: f64,
    v: f64,
    z: f64,
    band: f64,
}

impl RayPoint {
    fn new(index: usize, u: f64, v: f64, z: f64, noise: &DepthNoise) -> Self {
        Self { index, u, v, z, band: SURFACE_SIGMAS * noise.sigma_at(z) }
    }

    /// The pixel and depth a fit is made to.
    fn sample(&self) -> (f64, f64, f64) {
        (self.u, self.v, self.z)
    }
}

/// Inverse depth as an affine function of the pixel about the block's middle.
#[derive(Debug, Clone, Copy)]
struct InverseDepthPlane {
    middle: (f64, f64),
    coefficients: Vector3<f64>,
}

impl InverseDepthPlane {
    fn inverse_depth(&self, u: f64, v: f64) -> f64 {
        let c = &self.coefficients;
        c.x + c.y * (u - self.middle.0) + c.z * (v - self.middle.1)
    }

    fn holds(&self, point: &RayPoint) -> bool {
        let inverse = self.inverse_depth(point.u, point.v);
        inverse > 0.0 && (point.z - 1.0 / inverse).abs() <= point.band
    }

    /// The least-squares fit to `points` (pixel and depth); `None` when they do not fix one.
    fn fit(points: &[(f64, f64, f64)]) -> Option<Self> {
        let n = points.len() as f64;
        let middle = (
            points.iter().map(|p| p.0).sum::<f64>() / n,
            points.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let (mut normal, mut right) = (Matrix3::zeros(), Vector3::zeros());
        for &(u, v, z) in points {
            let row = Vector3::new(1.0, u - middle.0, v - middle.1);
            normal += row * row.transpose();
            right += row / z;
        }
        // Points along one row (or column) of pixels fix the inverse depth along it and nothing
        // across it (a strip of the tag's colour at a block's edge): the slope across is left
        // at naught, not found from the rounding of pixels found again from points.
        for across in [1, 2] {
            if normal[(across, across)] < ONE_LINE_SPREAD * n {
                normal.row_mut(across).fill(0.0);
                normal.column_mut(across).fill(0.0);
                normal[(across, across)] = 1.0;
                right[across] = 0.0;
            }
        }
        let coefficients = normal.try_inverse()? * right;
        Some(Self { middle, coefficients })
    }
}

/// The surface most of a block's points lie on: first those within the noise of the block's
/// median depth, then, twice, those within the noise of the fit to the last ones.
///
/// A fit to the very points the last one was made to is that same fit, so once a round keeps
/// the points it was given (on a clean surface, the first), the rounds left would only repeat
/// it; and the points the last round keeps are never read.
fn surface_of(
    members: &[RayPoint],
    noise: &DepthNoise,
    scratch: &mut Scratch,
) -> Option<InverseDepthPlane> {
    let Scratch { depths, on, kept } = scratch;
    depths.clear();
    depths.extend(members.iter().map(|m| m.z));
    let half = depths.len() / 2;
    let median = *depths.select_nth_unstable_by(half, f64::total_cmp).1;
    let band = SURFACE_SIGMAS * noise.sigma_at(median);
    kept.clear();
    kept.extend(members.iter().map(|m| (m.z - median).abs() <= band));
    on.clear();
    on.extend(members.iter().zip(kept.iter()).filter(|(_, k)| **k).map(|(m, _)| m.sample()));
    let mut rounds = 0;
    loop {
        if on.len() < MIN_BLOCK_POINTS {
            return None;
        }
        let plane = InverseDepthPlane::fit(on)?;
        rounds += 1;
        if rounds == 3 {
            return Some(plane);
        }
        let mut changed = false;
        for (m, k) in members.iter().zip(kept.iter_mut()) {
            let holds = plane.holds(m);
            changed |= holds != *k;
            *k = holds;
        }
        if !changed {
            return Some(plane);
        }
        on.clear();
        on.extend(members.iter().zip(kept.iter()).filter(|(_, k)| **k).map(|(m, _)| m.sample()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hal::CameraIntrinsics;
    use crate::perception::{DepthImage, DepthRange, PixelWindow, organised_cloud_from_depth_in};
    use nalgebra::Isometry3;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn smoothing<'a>(
        image: &'a ColorImage,
        tag: &'a HsvThresholds,
        calibration: &'a CameraCalibration,
        (min, max): (Point3<f64>, Point3<f64>),
        window: u32,
        noise: &'a DepthNoise,
    ) -> RaySmoothing<'a> {
        RaySmoothing { image, tag, calibration, min, max, window, noise }
    }

    fn camera() -> CameraCalibration {
        CameraCalibration {
            intrinsics: CameraIntrinsics {
                width: 200,
                height: 200,
                fx: 200.0,
                fy: 200.0,
                cx: 100.0,
                cy: 100.0,
            },
            base_from_camera: Isometry3::identity(),
        }
    }

    /// A plane `z = 4 + 0.5·x` seen by every pixel, its depth scattered by the noise at 4 m;
    /// a post 1 m nearer over columns 90–110.
    fn noisy_wall_and_post(noise: &DepthNoise, rng: &mut ChaCha8Rng) -> Vec<Point3<f32>> {
        let mut points = Vec::new();
        for v in 0..200 {
            for u in 0..200 {
                let (x, y) =
                    ((f64::from(u) + 0.5 - 100.0) / 200.0, (f64::from(v) + 0.5 - 100.0) / 200.0);
                // The ray (x, y, 1) meets z = 4 + 0.5·x·z at z = 4 / (1 − 0.5·x).
                let mut z = 4.0 / (1.0 - 0.5 * x);
                if (90..110).contains(&u) {
                    z -= 1.0;
                }
                let sigma = noise.sigma_at(z);
                let scatter: f64 = (0..12).map(|_| rng.random_range(-0.5..0.5)).sum();
                z += sigma * scatter;
                points.push(Point3::new(x * z, y * z, z).cast());
            }
        }
        points
    }

    #[test]
    fn a_noisy_wall_comes_out_flat_and_a_post_before_it_stays_apart() {
        let noise = DepthNoise::disparity(450.0, 0.05, 0.1);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let points = noisy_wall_and_post(&noise, &mut rng);
        let (min, max) = (Point3::new(-10.0, -10.0, 0.0), Point3::new(10.0, 10.0, 10.0));
        let image = ColorImage::new(200, 200);
        let tag = HsvThresholds::default();
        let smoothed =
            smoothing(&image, &tag, &camera(), (min, max), 12, &noise).of_points(&points);
        let wall_error = |p: &Point3<f32>| {
            let p = p.cast::<f64>();
            (p.z - 4.0 - 0.5 * p.x).abs()
        };
        let rms = |ps: &[Point3<f32>], keep: &dyn Fn(usize) -> bool| {
            let e: Vec<f64> = ps
                .iter()
                .enumerate()
                .filter(|(i, _)| keep(*i))
                .map(|(_, p)| wall_error(p))
                .collect();
            (e.iter().map(|e| e * e).sum::<f64>() / e.len() as f64).sqrt()
        };
        let on_wall = |i: usize| !(84..116).contains(&(i % 200));
        let (before, after) = (rms(&points, &on_wall), rms(&smoothed, &on_wall));
        assert!(before > 0.06, "the wall scatters by {before:.3} m");
        assert!(after < before / 4.0, "smoothed: {after:.3} m, raw {before:.3} m");
        // Each point stays on its ray, and the post stays a metre before the wall.
        for (raw, new) in points.iter().zip(&smoothed) {
            let (a, b) = (raw.coords.normalize(), new.coords.normalize());
            assert!((a - b).norm() < 1e-5);
        }
        let post: Vec<f64> = smoothed
            .iter()
            .enumerate()
            .filter(|(i, _)| (94..106).contains(&(i % 200)))
            .map(|(_, p)| wall_error(p))
            .collect();
        let post_mean = post.iter().sum::<f64>() / post.len() as f64;
        assert!(post_mean > 0.8, "the post sits {post_mean:.2} m before the wall");
    }

    /// A camera 1.2 m up, turned and tilted, looking at a noisy wall 2.5–4 m away with a post
    /// before it; a red patch on the wall, holes scattered over the frame, and a strip of red one
    /// row high at a block's edge. Returns the depth and the colour image.
    fn organised_frame(
        calibration: &CameraCalibration,
        noise: &DepthNoise,
        rng: &mut ChaCha8Rng,
    ) -> (DepthImage, ColorImage) {
        let k = &calibration.intrinsics;
        let (width, height) = (k.width, k.height);
        let mut image = ColorImage::new(width, height);
        let mut metres = Vec::new();
        for v in 0..height {
            for u in 0..width {
                let x = (f64::from(u) + 0.5 - k.cx) / k.fx;
                let mut z = 3.0 / (1.0 - 0.4 * x);
                if (70..84).contains(&u) {
                    z -= 0.8;
                }
                let scatter: f64 = (0..12).map(|_| rng.random_range(-0.5..0.5)).sum();
                z += noise.sigma_at(z) * scatter;
                let hole = rng.random_range(0.0..1.0) < 0.03;
                metres.push(if hole { 0.0 } else { z as f32 });
                let red = ((100..130).contains(&u) && (40..70).contains(&v))
                    || ((20..60).contains(&u) && v == 95);
                if red {
                    let i = (v as usize * width as usize + u as usize) * 3;
                    image.rgb[i..i + 3].copy_from_slice(&[200, 20, 20]);
                }
            }
        }
        (DepthImage::from_metres(width, height, &metres).unwrap(), image)
    }

    #[test]
    fn an_organised_frame_smooths_as_its_points_do_when_projected() {
        let calibration = CameraCalibration {
            intrinsics: CameraIntrinsics {
                width: 160,
                height: 120,
                fx: 140.0,
                fy: 140.0,
                cx: 81.3,
                cy: 58.9,
            },
            base_from_camera: Isometry3::new(
                Vector3::new(0.1, -0.2, 1.2),
                Vector3::new(-1.9, 0.15, -1.4),
            ),
        };
        let noise = DepthNoise::disparity(450.0, 0.05, 0.1);
        let mut rng = ChaCha8Rng::seed_from_u64(34);
        let (depth, image) = organised_frame(&calibration, &noise, &mut rng);
        let tag = HsvThresholds::default();
        // A box that leaves part of the frame out, and a window that leaves some pixels out.
        let cloud = organised_cloud_from_depth_in(
            &depth,
            &calibration,
            &DepthRange::default(),
            &PixelWindow { columns: [7, 150], rows: [3, 117] },
        )
        .unwrap();
        let points = cloud.cloud().points.clone();
        let centre = points[points.len() / 2].cast::<f64>();
        let (min, max) = (centre - Vector3::repeat(1.5), centre + Vector3::repeat(1.5));
        let outside = points.iter().filter(|p| !inside(&p.cast(), &min, &max)).count();
        assert!(outside > 1000, "{outside} points outside the box");
        for window in [3, 6, 10] {
            let smoothing = smoothing(&image, &tag, &calibration, (min, max), window, &noise);
            let projected = smoothing.of_points(&points);
            let mut organised = cloud.clone();
            smoothing.of_organised(&mut organised);
            let mut moved = 0;
            for (i, ((a, b), raw)) in
                projected.iter().zip(&organised.cloud().points).zip(&points).enumerate()
            {
                // A pixel found again from a point of single precision is off by about 1e-4
                // of a pixel, its depth by 1e-7 of itself: the fits differ in their last bits.
                assert!((a - b).norm() <= 1e-5, "window {window}, point {i}: {a} against {b}");
                moved += usize::from((a - raw).norm() > 1e-3);
            }
            assert!(moved > points.len() / 3, "window {window}: {moved} moved");
        }
    }

    #[test]
    fn points_along_one_row_are_fitted_along_it_alone() {
        // Inverse depth 0.25 + 0.001 (u − 10.5) along row 7, scattered; and the same points with
        // their rows off by the rounding a projection leaves.
        let row: Vec<(f64, f64, f64)> = (0..8)
            .map(|i| {
                let u = 10.5 + f64::from(i);
                let scatter = [0.002, -0.001, 0.0, 0.003, -0.002, 0.001, -0.003, 0.0][i as usize];
                (u, 7.5, 1.0 / (0.25 + 0.001 * (u - 10.5) + scatter))
            })
            .collect();
        let jittered: Vec<(f64, f64, f64)> =
            row.iter().enumerate().map(|(i, &(u, v, z))| (u, v + 1e-6 * i as f64, z)).collect();
        let (a, b) =
            (InverseDepthPlane::fit(&row).unwrap(), InverseDepthPlane::fit(&jittered).unwrap());
        assert_eq!(a.coefficients.z, 0.0);
        for &(u, v, _) in &row {
            let (fa, fb) = (a.inverse_depth(u, v), b.inverse_depth(u, v));
            assert!((fa - fb).abs() < 1e-12, "at {u}: {fa} against {fb}");
        }
        // The least-squares line through the row: at its middle (u = 14) the mean, 0.2535 (the
        // scatter sums to naught), and its slope 0.001 − Σ(u − ū)·scatter / Σ(u − ū)² = 0.013 / 42.
        assert!((a.coefficients.x - 0.2535).abs() < 1e-12, "{}", a.coefficients);
        assert!((a.coefficients.y - (0.001 - 0.013 / 42.0)).abs() < 1e-12, "{}", a.coefficients);
    }

    #[test]
    fn a_one_pixel_window_moves_nothing() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let noise = DepthNoise::LASER;
        let points = noisy_wall_and_post(&noise, &mut rng);
        let (min, max) = (Point3::new(-10.0, -10.0, 0.0), Point3::new(10.0, 10.0, 10.0));
        let (image, tag) = (ColorImage::new(200, 200), HsvThresholds::default());
        let smoothed = smoothing(&image, &tag, &camera(), (min, max), 1, &noise).of_points(&points);
        assert_eq!(smoothed, points);
    }

    #[test]
    fn blocks_too_small_for_a_fit_move_nothing_and_the_next_size_smooths() {
        let noise = DepthNoise::disparity(450.0, 0.05, 0.1);
        let points = noisy_wall_and_post(&noise, &mut ChaCha8Rng::seed_from_u64(5));
        let (min, max) = (Point3::new(-10.0, -10.0, 0.0), Point3::new(10.0, 10.0, 10.0));
        let (image, tag) = (ColorImage::new(200, 200), HsvThresholds::default());
        let smoothed = |window| {
            smoothing(&image, &tag, &camera(), (min, max), window, &noise).of_points(&points)
        };
        // Two pixels a side hold 4 of the frame's points, fewer than a fit needs; three hold 9.
        assert_eq!(smoothed(2), points);
        let moved = smoothed(3).iter().zip(&points).filter(|(a, b)| a != b).count();
        assert!(moved > points.len() / 2, "{moved} of {} points moved", points.len());
    }
}
