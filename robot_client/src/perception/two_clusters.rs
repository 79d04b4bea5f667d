//! A red region of two things, seen voxel by voxel (issue 34): a red plastic lying against a
//! tag of nearly its colour, or standing a few millimetres prouder than it on the same
//! surface. Each point carries a measure, a point of the plane: its colour on the chroma disc,
//! or its distance from a surface on the first axis. Point by point the two things' measures
//! overlap in the sensors' noise; the mean over the points a 1 cm voxel holds overlaps less;
//! and since the tag and the thing against it are each a piece of surface centimetres across,
//! a voxel's mean pooled with its neighbours' overlaps least. Two tight clusters of pooled
//! means, far apart for their spreads, are two things, and the tag is the one its part nearest
//! the target is in.

use nalgebra::Point3;
use rustc_hash::FxHashMap;

use super::voxel_coords::cube_of;

/// How far apart the two clusters' middles must be, in their pooled standard deviations: at
/// four, a voxel of either thing falls on the other's side of the midpoint in 2.3 % of cases.
const SEPARATION_SIGMAS: f32 = 4.0;

/// Rounds of moving each middle to the mean of the voxels nearest it; two clusters settle in a
/// handful.
const ROUNDS: usize = 20;

/// The points of one of a region's two things.
pub(super) struct CoreHalf {
    /// Which of the points, by index.
    pub kept: Vec<usize>,
    /// The other thing's middle measure.
    pub other: [f32; 2],
    /// The two middles' distance, and the pooled spread of the voxels about them.
    pub distance: f32,
    pub spread: f32,
}

/// The points in the voxels of the cluster the `core` points are in, when the region's voxels'
/// pooled `measures` fall into two clusters at least `SEPARATION_SIGMAS` apart and the other
/// holds at least `least` points; `None` when they are one thing. A point without a measure
/// (outside the picture) is in no voxel.
pub(super) fn of_the_core_cluster(
    points: &[Point3<f32>],
    measures: &[Option<[f32; 2]>],
    core: &[usize],
    voxel_size: f32,
    least: usize,
) -> Option<CoreHalf> {
    let voxels = pooled_with_neighbours(voxel_means(points, measures, voxel_size));
    if voxels.len() < 2 {
        return None;
    }
    // Each point's voxel, `None` for a point outside the picture.
    let mut of_point: Vec<Option<usize>> = vec![None; points.len()];
    for (v, voxel) in voxels.iter().enumerate() {
        for &i in &voxel.members {
            of_point[i] = Some(v);
        }
    }
    let core_voxels: Vec<usize> = core.iter().filter_map(|&i| of_point[i]).collect();
    let core_mean = weighted_mean(core_voxels.iter().map(|&v| &voxels[v]))?;
    let mut middles = [core_mean, far_half_mean(&voxels, core_mean)?];
    let mut side = vec![0usize; voxels.len()];
    for _ in 0..ROUNDS {
        let assigned: Vec<usize> = voxels.iter().map(|v| nearer(v.mean, &middles)).collect();
        let settled = assigned == side;
        side = assigned;
        for (which, middle) in middles.iter_mut().enumerate() {
            let members = voxels.iter().zip(&side).filter(|(_, s)| **s == which).map(|(v, _)| v);
            if let Some(mean) = weighted_mean(members) {
                *middle = mean;
            }
        }
        if settled {
            break;
        }
    }
    let (squares, weight) = voxels.iter().zip(&side).fold((0.0, 0.0), |(sum, n), (v, s)| {
        (sum + v.weight() * distance(v.mean, middles[*s]).powi(2), n + v.weight())
    });
    let spread = (squares / weight).sqrt();
    let apart = distance(middles[0], middles[1]);
    // A NaN spread (no weight) parts nothing either.
    if apart.is_nan() || spread.is_nan() || apart < SEPARATION_SIGMAS * spread {
        return None;
    }
    let core_side =
        usize::from(core_voxels.iter().filter(|&&v| side[v] == 1).count() * 2 > core_voxels.len());
    let kept: Vec<usize> = voxels
        .iter()
        .zip(&side)
        .filter(|(_, s)| **s == core_side)
        .flat_map(|(v, _)| v.members.iter().copied())
        .collect();
    let other = voxels.iter().zip(&side).filter(|(_, s)| **s != core_side);
    let others: usize = other.map(|(v, _)| v.members.len()).sum();
    let half = CoreHalf { kept, other: middles[1 - core_side], distance: apart, spread };
    (others >= least && !half.kept.is_empty()).then_some(half)
}

/// One voxel's points: their mean measure and which points they are.
struct VoxelMean {
    cube: [i64; 3],
    mean: [f32; 2],
    members: Vec<usize>,
}

impl VoxelMean {
    fn weight(&self) -> f32 {
        self.members.len() as f32
    }
}

/// The measured points grouped by voxel, in the order their first point comes.
fn voxel_means(
    points: &[Point3<f32>],
    measures: &[Option<[f32; 2]>],
    voxel_size: f32,
) -> Vec<VoxelMean> {
    // Voxels of one frame, chosen by nobody: SipHash buys nothing here.
    let mut index: FxHashMap<[i64; 3], usize> = FxHashMap::default();
    let mut sums: Vec<([i64; 3], [f32; 2], Vec<usize>)> = Vec::new();
    for (i, (p, measure)) in points.iter().zip(measures).enumerate() {
        let Some(c) = measure else { continue };
        let cube = cube_of(p, voxel_size);
        let v = *index.entry(cube).or_insert_with(|| {
            sums.push((cube, [0.0; 2], Vec::new()));
            sums.len() - 1
        });
        sums[v].1[0] += c[0];
        sums[v].1[1] += c[1];
        sums[v].2.push(i);
    }
    sums.into_iter()
        .map(|(cube, sum, members)| {
            let n = members.len() as f32;
            VoxelMean { cube, mean: [sum[0] / n, sum[1] / n], members }
        })
        .collect()
}

/// Each voxel's measure as the mean over the points of the voxels around it (the 3 × 3 × 3
/// voxels centred on it, those that hold points): the camera's noise falls by about the root of
/// the number pooled, nine or so on a surface, while only the voxels along the boundary of two
/// things mix their measures.
fn pooled_with_neighbours(voxels: Vec<VoxelMean>) -> Vec<VoxelMean> {
    let at: FxHashMap<[i64; 3], usize> =
        voxels.iter().enumerate().map(|(i, v)| (v.cube, i)).collect();
    let pooled: Vec<[f32; 2]> = voxels
        .iter()
        .map(|v| {
            let neighbours = (-1..=1)
                .flat_map(|x| (-1..=1).flat_map(move |y| (-1..=1).map(move |z| [x, y, z])))
                .filter_map(|[x, y, z]| at.get(&[v.cube[0] + x, v.cube[1] + y, v.cube[2] + z]));
            weighted_mean(neighbours.map(|&n| &voxels[n])).unwrap_or(v.mean)
        })
        .collect();
    voxels.into_iter().zip(pooled).map(|(v, mean)| VoxelMean { mean, ..v }).collect()
}

/// The mean measure of the voxels farther from `from` than half of the points are: the other
/// thing's first guess. The single farthest voxel would be an odd one (a stray pixel's
/// voxel that has no neighbours to pool with), and the two clusters would settle into it and
/// the rest.
fn far_half_mean(voxels: &[VoxelMean], from: [f32; 2]) -> Option<[f32; 2]> {
    let mut by_distance: Vec<&VoxelMean> = voxels.iter().collect();
    by_distance.sort_by(|a, b| distance(a.mean, from).total_cmp(&distance(b.mean, from)));
    let half = by_distance.iter().map(|v| v.weight()).sum::<f32>() / 2.0;
    let mut nearer = 0.0;
    let far = by_distance.into_iter().skip_while(|v| {
        nearer += v.weight();
        nearer <= half
    });
    weighted_mean(far)
}

fn weighted_mean<'a>(voxels: impl Iterator<Item = &'a VoxelMean>) -> Option<[f32; 2]> {
    let (sum, n) = voxels.fold(([0.0f32; 2], 0.0f32), |(s, n), v| {
        ([s[0] + v.mean[0] * v.weight(), s[1] + v.mean[1] * v.weight()], n + v.weight())
    });
    (n > 0.0).then(|| [sum[0] / n, sum[1] / n])
}

fn distance(a: [f32; 2], b: [f32; 2]) -> f32 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn nearer(measure: [f32; 2], middles: &[[f32; 2]; 2]) -> usize {
    usize::from(distance(measure, middles[1]) < distance(measure, middles[0]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A 6 × 8 cm tag beside a 20 × 20 cm plastic on one plane, 30 points a voxel, each pixel's
    /// colour scattered by `noise` about its thing's: the tag at hue 4°, saturation 0.77; the
    /// plastic at 357°, 0.69 (0.12 apart on the chroma disc).
    fn tag_and_plastic(
        noise: f32,
        plastic: [f32; 2],
        seed: u64,
    ) -> (Vec<Point3<f32>>, Vec<[f32; 2]>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let tag = [0.768, 0.054];
        let (mut points, mut colours) = (Vec::new(), Vec::new());
        for i in 0..26 {
            for j in 0..20 {
                let (y, z) = (i as f32 * 0.01 + 0.005, j as f32 * 0.01 + 0.005);
                let colour = if y < 0.06 && z < 0.08 {
                    tag
                } else if y >= 0.06 {
                    plastic
                } else {
                    continue;
                };
                for _ in 0..30 {
                    let jitter = [rng.random_range(-0.004..0.004), rng.random_range(-0.004..0.004)];
                    points.push(Point3::new(1.0, y + jitter[0], z + jitter[1]));
                    let scatter =
                        [rng.random_range(-noise..noise), rng.random_range(-noise..noise)];
                    colours.push([colour[0] + scatter[0], colour[1] + scatter[1]]);
                }
            }
        }
        (points, colours)
    }

    #[test]
    fn a_plastic_of_nearly_the_tags_colour_is_parted_voxel_by_voxel() {
        for seed in 0..10 {
            // Per pixel the two overlap: a spread of 0.09 (uniform ±0.15) against 0.12 apart.
            let (points, colours) = tag_and_plastic(0.15, [0.689, -0.036], seed);
            let coloured: Vec<Option<[f32; 2]>> = colours.iter().map(|c| Some(*c)).collect();
            let core: Vec<usize> = (0..points.len()).filter(|&i| points[i].y < 0.02).collect();
            let half =
                of_the_core_cluster(&points, &coloured, &core, 0.01, 30).expect("two colours");
            let tag_points = 6 * 8 * 30;
            let plastic_kept = half.kept.iter().filter(|&&i| points[i].y >= 0.065).count();
            assert_eq!(plastic_kept, 0, "seed {seed}: none of the plastic's middle stays");
            assert!(half.kept.len() >= tag_points * 9 / 10, "seed {seed}: {}", half.kept.len());
        }
    }

    #[test]
    fn a_stray_pixel_of_another_colour_does_not_become_one_of_the_two() {
        for seed in 0..10 {
            let (mut points, mut colours) = tag_and_plastic(0.15, [0.689, -0.036], seed);
            // One pixel of orange 10 cm off the plastic's edge, alone in its voxel.
            points.push(Point3::new(1.0, 0.36, 0.05));
            colours.push([0.2, 0.5]);
            let coloured: Vec<Option<[f32; 2]>> = colours.iter().map(|c| Some(*c)).collect();
            let core: Vec<usize> = (0..points.len()).filter(|&i| points[i].y < 0.02).collect();
            let half =
                of_the_core_cluster(&points, &coloured, &core, 0.01, 30).expect("two colours");
            let plastic_kept =
                half.kept.iter().filter(|&&i| (0.065..0.26).contains(&points[i].y)).count();
            assert_eq!(plastic_kept, 0, "seed {seed}: none of the plastic's middle stays");
        }
    }

    #[test]
    fn one_colour_is_not_parted() {
        for seed in 0..10 {
            let (points, colours) = tag_and_plastic(0.15, [0.768, 0.054], seed);
            let coloured: Vec<Option<[f32; 2]>> = colours.iter().map(|c| Some(*c)).collect();
            let core: Vec<usize> = (0..points.len()).filter(|&i| points[i].y < 0.02).collect();
            assert!(
                of_the_core_cluster(&points, &coloured, &core, 0.01, 30).is_none(),
                "seed {seed}"
            );
        }
    }
}
