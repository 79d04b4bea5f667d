//! Multi-plane RANSAC: every plane in the volume of interest (paper §IV-B.1.a, where the robot
//! used MLESAC from ROS to "find all planes"), dropping those under 100 points and, beyond the
//! paper, slabs that are not surfaces (see [`super::plane_evidence`]).
//!
//! Speed comes from four choices: a depth camera's cloud, tens of points where the laser puts
//! one, is thinned to about the laser's spacing before the search (see [`thinning_stride`]);
//! the second and third sample points are drawn from the first one's 10 cm cell, so a sample
//! lies on one surface far more often than three points drawn from the whole volume; hypotheses
//! are scored on a fixed random subset; and the iteration count adapts to the best support
//! found so far (the usual RANSAC stopping rule). The refits that follow read only the points
//! near the hypothesis while that is provably enough ([`super::refit`]).
//!
//! The band hypotheses are scored in is fixed; the band a plane is finally judged and kept in is
//! measured from the plane's own noise (see [`super::plane_evidence`]).

use nalgebra::Point3;
use rand::Rng;

use super::cells::CellIndex;
use super::plane::Plane;
use super::plane_evidence::{PlaneEvidenceRule, assess_plane_among};
use super::refit::{Refit, bounds};
use super::rejection::RejectedPlane;

/// The knobs of the plane search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneSearchParams {
    /// Half-width of the band hypotheses are scored and refitted in, metres.
    pub inlier_distance: f64,
    /// Side of the cells the second and third sample points are drawn from, metres.
    pub sample_cell: f32,
    /// Points hypotheses are scored on.
    pub score_sample: usize,
    pub min_iterations: usize,
    pub max_iterations: usize,
    /// Probability of having drawn one all-inlier sample when the search for a plane stops.
    pub confidence: f64,
    /// Most planes to report.
    pub max_planes: usize,
    /// Consecutive rejected hypotheses after which the search gives up.
    pub max_rejections: usize,
    /// Spacing, metres, a denser cloud is thinned to before the search: the laser's 0.5° beam
    /// step at 0.9 m, among the densest scans the evidence rule was made on. At 1 cm a drawer
    /// front's sparsely seen edges emptied their 4 cm cells and its fill fell just below the
    /// rule's; at 0.8 cm a quarter-filled cell still holds a few points.
    pub thinned_spacing: f32,
    pub evidence: PlaneEvidenceRule,
}

impl Default for PlaneSearchParams {
    fn default() -> Self {
        Self {
            inlier_distance: 0.015,
            sample_cell: 0.1,
            score_sample: 3000,
            min_iterations: 12,
            max_iterations: 400,
            confidence: 0.995,
            max_planes: 12,
            max_rejections: 6,
            thinned_spacing: 0.008,
            evidence: PlaneEvidenceRule::default(),
        }
    }
}

impl PlaneSearchParams {
    /// These parameters for depths scattering with standard deviation `sigma` (metres) about
    /// the target: hypotheses are scored in a band that holds a surface's noise, and the
    /// judging may measure and take in a band of up to twice the noise expected. Below the
    /// laser's noise, unchanged.
    pub fn for_depth_noise(&self, sigma: f64) -> Self {
        let mut params = *self;
        params.inlier_distance = self.inlier_distance.max(2.5 * sigma);
        params.sample_cell = self.sample_cell.max((4.0 * sigma) as f32);
        params.evidence.max_band = self.evidence.max_band.max(2.0 * 2.5 * sigma);
        params.evidence.max_waviness = self.evidence.max_waviness.max(0.7 * sigma);
        params
    }
}

/// A plane found in the cloud, its normal toward the viewpoint.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectedPlane {
    pub plane: Plane,
    pub centroid: Point3<f64>,
    /// Indices of its points in the searched cloud (of a dense cloud, the thinned-to points).
    pub inliers: Vec<u32>,
    /// Widths along its major and minor in-plane axes, metres.
    pub extent: [f64; 2],
    /// The laser's noise across it (standard deviation, metres) and the band its inliers lie in.
    pub noise: f64,
    pub inlier_distance: f64,
}

/// What the plane search found, and what it judged not to be a surface.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlaneSearch {
    /// Largest support first, normals toward the viewpoint.
    pub planes: Vec<DetectedPlane>,
    /// Hypotheses that held many points but failed the evidence test, in the order tried.
    pub rejected: Vec<RejectedPlane>,
}

/// Every plane in `points`, largest support first, normals toward `viewpoint`.
pub fn find_planes(
    points: &[Point3<f32>],
    viewpoint: &Point3<f64>,
    params: &PlaneSearchParams,
    rng: &mut impl Rng,
) -> PlaneSearch {
    let stride = thinning_stride(points, params.thinned_spacing);
    if stride == 1 {
        return search_planes(points, viewpoint, params, rng);
    }
    let thinned: Vec<Point3<f32>> = points.iter().step_by(stride).copied().collect();
    let mut search = search_planes(&thinned, viewpoint, params, rng);
    for plane in &mut search.planes {
        for i in &mut plane.inliers {
            *i *= stride as u32;
        }
    }
    search
}

/// Pairs of consecutive points whose spacing is measured.
const SPACING_PAIRS: usize = 1024;

/// Every how many points of `points` to keep for them to lie about `spacing` apart: 1 for a
/// laser scan, more for a depth camera's dense cloud. An organised cloud's consecutive points
/// are neighbouring pixels (a scan's, neighbouring beams), so the median distance between
/// consecutive points is its spacing on the surfaces; keeping one point in `k` spreads them
/// over `k` times the area, √k times the spacing.
///
/// Why: a depth camera gives 10–50 times the laser's points on the same surface; the search
/// and the evidence rule need no more than the laser gives, and read every point several times.
fn thinning_stride(points: &[Point3<f32>], spacing: f32) -> usize {
    let pairs = points.len().saturating_sub(1);
    if pairs == 0 {
        return 1;
    }
    let step = pairs.div_ceil(SPACING_PAIRS);
    let mut gaps: Vec<f32> =
        (0..pairs).step_by(step).map(|i| (points[i + 1] - points[i]).norm()).collect();
    let middle = gaps.len() / 2;
    let gap = *gaps.select_nth_unstable_by(middle, f32::total_cmp).1;
    if gap <= 0.0 {
        return 1;
    }
    ((spacing / gap).powi(2).floor() as usize).max(1)
}

/// [`find_planes`] over every point of `points`.
fn search_planes(
    points: &[Point3<f32>],
    viewpoint: &Point3<f64>,
    params: &PlaneSearchParams,
    rng: &mut impl Rng,
) -> PlaneSearch {
    let n = points.len();
    let mut search = PlaneSearch::default();
    if n < params.evidence.min_points || n >= u32::MAX as usize {
        return search;
    }
    let cells = CellIndex::new(points, params.sample_cell);
    let bounds = bounds(points);
    let t = params.inlier_distance;
    let PlaneSearch { planes, rejected } = &mut search;
    let subset: Vec<u32> = if n <= params.score_sample {
        (0..n as u32).collect()
    } else {
        (0..params.score_sample).map(|_| rng.random_range(0..n as u32)).collect()
    };
    let mut alive = vec![true; n];
    // Points of a rejected hypothesis stay in the cloud (they may lie on a real surface the
    // hypothesis cut across) but no longer seed samples, so the search moves on.
    let mut seedable = vec![true; n];
    // The alive points and the seedable ones among them, ascending, kept as the search
    // removes points rather than gathered anew for every plane.
    let mut alive_indices: Vec<u32> = (0..n as u32).collect();
    let mut seeds = alive_indices.clone();
    let mut rejections = 0;
    while planes.len() < params.max_planes
        && alive_indices.len() >= params.evidence.min_points
        && rejections < params.max_rejections
    {
        if seeds.is_empty() {
            break;
        }
        let sample = ScoringSample::of(points, &subset, &alive);
        let alive_in_subset = sample.len().max(1);
        let mut best: Option<(Plane, i64)> = None;
        let mut needed = params.max_iterations;
        let mut iteration = 0;
        while iteration < needed.max(params.min_iterations) {
            iteration += 1;
            let Some(plane) = sample_plane(&cells, points, &alive, &seeds, rng) else {
                continue;
            };
            let score = sample.score(&plane, t);
            if best.is_none_or(|(_, s)| score > s) {
                best = Some((plane, score));
                let w = (score.max(0) as f64 / alive_in_subset as f64).clamp(1e-6, 1.0);
                // A local sample is all-inlier about 70% of the time its first point is.
                let p_good = (0.7 * w).min(0.999);
                needed = ((1.0 - params.confidence).ln() / (1.0 - p_good).ln()).ceil() as usize;
                needed = needed.clamp(params.min_iterations, params.max_iterations);
            }
        }
        let Some((hypothesis, score)) = best else { break };
        if score <= 0 {
            break;
        }
        // Refit to the inliers, narrowing the band, so that a sample straddling a surface and
        // something just proud of it (a towel on a drawer) settles on the surface; then judge it.
        // The points near the hypothesis are gathered once, in a window that holds, with room
        // for the refit to move the plane, the widest band the judging reads.
        let window = params.evidence.window().max(t) + 2.0 * t;
        let refit = Refit::around(points, &alive_indices, hypothesis, window, &bounds);
        let refined = refit.refine(&[t, 0.6 * t, 0.6 * t]);
        let near = refit.within(&refined, params.evidence.window());
        match assess_plane_among(points, near, &refined, &params.evidence) {
            Ok(patch) => {
                rejections = 0;
                // The surface's whole noise band goes, lest its fringes come back as phantom planes.
                for &i in &patch.band {
                    alive[i as usize] = false;
                }
                alive_indices.retain(|&i| alive[i as usize]);
                seeds.retain(|&i| alive[i as usize]);
                let (plane, centroid) =
                    Plane::fit(patch.inliers.iter().map(|&i| points[i as usize].cast()))
                        .unwrap_or((refined, Point3::origin()));
                planes.push(DetectedPlane {
                    plane: plane.facing(viewpoint),
                    centroid,
                    inliers: patch.inliers,
                    extent: patch.extent,
                    noise: patch.noise,
                    inlier_distance: patch.inlier_distance,
                });
            }
            Err(why) => {
                rejections += 1;
                let mut within = 0;
                for i in refit.within(&refined, t) {
                    seedable[i as usize] = false;
                    within += 1;
                }
                seeds.retain(|&i| seedable[i as usize]);
                let plane = refined.facing(viewpoint);
                rejected.push(RejectedPlane {
                    normal: plane.normal,
                    offset: plane.offset,
                    points: within,
                    why,
                });
            }
        }
    }
    search
}

/// The alive points of the scoring subset, each coordinate in its own array, so that scoring a
/// hypothesis — the loop RANSAC spends its time in — is one pass of vector arithmetic.
struct ScoringSample {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
}

impl ScoringSample {
    fn of(points: &[Point3<f32>], subset: &[u32], alive: &[bool]) -> Self {
        let room = || Vec::with_capacity(subset.len());
        let mut sample = Self { x: room(), y: room(), z: room() };
        for p in subset.iter().filter(|&&i| alive[i as usize]).map(|&i| &points[i as usize]) {
            sample.x.push(p.x);
            sample.y.push(p.y);
            sample.z.push(p.z);
        }
        sample
    }

    fn len(&self) -> usize {
        self.x.len()
    }

    /// Support minus the points just outside the band: a slab through a volume scores ~0.
    fn score(&self, plane: &Plane, band: f64) -> i64 {
        let [a, b, c] = [plane.normal.x, plane.normal.y, plane.normal.z].map(|v| v as f32);
        let (d, t) = (plane.offset as f32, band as f32);
        let (mut near, mut outside) = (0u32, 0u32);
        for ((&x, &y), &z) in self.x.iter().zip(&self.y).zip(&self.z) {
            let distance = (a * x + b * y + c * z + d).abs();
            near += u32::from(distance < t);
            outside += u32::from((distance >= t) & (distance < 2.0 * t));
        }
        i64::from(near) - i64::from(outside)
    }
}

/// A plane through a random seed point and two alive points of its cell: a sample of three
/// points close together lies on one surface far more often than three drawn from anywhere.
fn sample_plane(
    cells: &CellIndex,
    points: &[Point3<f32>],
    alive: &[bool],
    seeds: &[u32],
    rng: &mut impl Rng,
) -> Option<Plane> {
    let first = *seeds.get(rng.random_range(0..seeds.len().max(1)))?;
    let cell = cells.cell_of(first);
    if cell.len() < 3 {
        return None;
    }
    let mut pick = || {
        (0..8)
            .map(|_| cell[rng.random_range(0..cell.len())])
            .find(|&i| i != first && alive[i as usize])
    };
    let (second, third) = (pick()?, pick()?);
    if second == third {
        return None;
    }
    Plane::through(
        &points[first as usize].cast(),
        &points[second as usize].cast(),
        &points[third as usize].cast(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// A standard normal sample for test data (the navigation code never touches the simulator).
    fn gaussian(rng: &mut ChaCha8Rng) -> f32 {
        crate::sim::gaussian(rng) as f32
    }

    /// A wall at x = 2 (1 m wide, 1 m tall), a floor patch, and a cube of dense volumetric noise.
    fn wall_floor_and_noise(rng: &mut ChaCha8Rng) -> Vec<Point3<f32>> {
        let mut points = Vec::new();
        for _ in 0..6000 {
            points.push(Point3::new(
                2.0 + 0.006 * gaussian(rng),
                rng.random_range(-0.5..0.5),
                rng.random_range(0.5..1.5),
            ));
        }
        for _ in 0..3000 {
            points.push(Point3::new(
                rng.random_range(1.0..1.9),
                rng.random_range(-0.5..0.5),
                0.006 * gaussian(rng),
            ));
        }
        // 20 000 points in 0.7 m × 0.8 m × 0.6 m: a 2 cm slab through it holds hundreds.
        for _ in 0..20_000 {
            points.push(Point3::new(
                rng.random_range(1.0..1.7),
                rng.random_range(-0.4..0.4),
                rng.random_range(0.1..0.7),
            ));
        }
        points
    }

    #[test]
    fn finds_the_surfaces_and_no_slab_of_noise() {
        for seed in 0..20 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let points = wall_floor_and_noise(&mut rng);
            let planes = find_planes(
                &points,
                &Point3::new(0.0, 0.0, 1.0),
                &PlaneSearchParams::default(),
                &mut rng,
            )
            .planes;
            let wall = planes.iter().filter(|p| p.plane.normal.dot(&-Vector3::x()) > 0.99).count();
            let floor = planes.iter().filter(|p| p.plane.normal.dot(&Vector3::z()) > 0.99).count();
            assert_eq!((wall, floor, planes.len()), (1, 1, 2), "seed {seed}: {planes:#?}");
            let wall = planes.iter().find(|p| p.plane.normal.x < -0.99).unwrap();
            assert!((wall.plane.offset - 2.0).abs() < 0.005 && wall.inliers.len() > 5000);
        }
    }

    /// A wall at x = 2 sampled on a grid `step` metres apart, row by row as a camera reads it.
    fn gridded_wall(step: f32, rng: &mut ChaCha8Rng) -> Vec<Point3<f32>> {
        let n = (0.8 / step) as usize;
        (0..n * n)
            .map(|i| {
                let (row, col) = ((i / n) as f32, (i % n) as f32);
                Point3::new(2.0 + 0.0005 * gaussian(rng), -0.4 + col * step, 0.6 + row * step)
            })
            .collect()
    }

    #[test]
    fn a_scan_is_searched_whole_and_a_dense_cloud_thinned_to_the_scans_spacing() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let spacing = PlaneSearchParams::default().thinned_spacing;
        assert_eq!(thinning_stride(&gridded_wall(0.012, &mut rng), spacing), 1);
        assert_eq!(thinning_stride(&gridded_wall(0.0025, &mut rng), spacing), 9);
        assert_eq!(thinning_stride(&[Point3::origin()], spacing), 1);
    }

    #[test]
    fn a_dense_walls_inliers_are_its_own_points() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let points = gridded_wall(0.0025, &mut rng);
        let planes = find_planes(
            &points,
            &Point3::new(0.0, 0.0, 1.0),
            &PlaneSearchParams::default(),
            &mut rng,
        )
        .planes;
        assert_eq!(planes.len(), 1, "{planes:#?}");
        let wall = &planes[0];
        assert!(wall.plane.normal.x < -0.999 && (wall.plane.offset - 2.0).abs() < 0.002);
        // One point in nine, nearly all of them: indices into the whole cloud.
        assert!(wall.inliers.iter().all(|&i| i % 9 == 0 && (i as usize) < points.len()));
        assert!(wall.inliers.len() > points.len() / 9 * 95 / 100, "{}", wall.inliers.len());
    }

    #[test]
    fn nothing_but_noise_holds_no_plane() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let points: Vec<Point3<f32>> = (0..30_000)
            .map(|_| {
                Point3::new(
                    rng.random_range(0.0..1.0),
                    rng.random_range(0.0..1.0),
                    rng.random_range(0.0..1.0),
                )
            })
            .collect();
        assert!(
            find_planes(&points, &Point3::origin(), &PlaneSearchParams::default(), &mut rng)
                .planes
                .is_empty()
        );
    }
}
