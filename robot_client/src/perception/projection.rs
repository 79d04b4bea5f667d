//! Projecting the laser cloud into the segmented image (paper §III-B: "Points projected onto
//! red-segmented regions are kept, all others are discarded").
//!
//! The camera and the laser sit apart, so the laser sees surfaces the camera does not (the wall
//! behind a pull chain, say). Projected naively, such a point lands on the red of whatever hides
//! it and is kept. So the cloud also acts as its own depth image: each small cell of the image
//! remembers the nearest depth projected into it, and a red point much deeper than that is
//! hidden from the camera and dropped.

use nalgebra::{Matrix3, Point3, Vector3};
use rayon::prelude::*;

use super::mask::Mask;
use crate::hal::CameraCalibration;

/// Points a core projects at a time: a cloud of 150k points is 37 blocks, so two cores finish
/// within a block of each other, and a block's own bookkeeping stays far below its work.
const PROJECTION_BLOCK: usize = 4096;

/// How the occlusion test sees the cloud.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OcclusionTest {
    /// Angular size of a depth cell, radians: a few laser beam spacings, so that a cell holds a
    /// point of the nearest surface even where the cloud is sparse.
    pub cell_angle: f64,
    /// How far behind the nearest depth of its cell a point may lie and still count as seen,
    /// metres: the depth a tag spans plus the laser's noise.
    pub tolerance: f32,
}

impl Default for OcclusionTest {
    fn default() -> Self {
        Self { cell_angle: 0.008, tolerance: 0.03 }
    }
}

/// The points of `cloud` (base frame) that project onto set pixels of `mask` and are not hidden
/// from the camera by nearer points.
pub fn points_on_mask(
    cloud: &[Point3<f32>],
    mask: &Mask,
    calibration: &CameraCalibration,
    occlusion: &OcclusionTest,
) -> Vec<Point3<f32>> {
    let everywhere = Reach { centre: Point3::origin(), radius: f64::INFINITY };
    ProjectedCloud::new(cloud, calibration, occlusion, &everywhere).on_mask(cloud, mask, occlusion)
}

/// The ball around the target that a tag's points can lie in (base frame, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    pub centre: Point3<f64>,
    pub radius: f64,
}

/// The cloud as the camera sees it: where each point that lands in the image lands and how
/// deep, and the nearest depth of every depth cell. Projected once, before the image is
/// segmented, so that the segmentation can start from the pixels the laser saw near the target.
#[derive(Debug, Clone)]
pub struct ProjectedCloud {
    width: usize,
    height: usize,
    /// Points in the cloud projected.
    points: usize,
    /// The points that land in the image, in the cloud's order, block by block as the cores
    /// projected them (joining the blocks would only copy them). A laser sees more of the room
    /// than the camera: most of its points land beside the picture and are not kept at all.
    landings: Vec<Vec<Landing>>,
    nearest: Vec<f32>,
    /// The pixels some point within the reach lands on.
    seen: Mask,
}

/// Where a point lands: its index in the cloud, its pixel, the depth cell of that pixel, its
/// depth along the optical axis (metres), and whether it lies within the reach.
#[derive(Debug, Clone, Copy)]
struct Landing {
    point: u32,
    x: u32,
    y: u32,
    cell: u32,
    depth: f32,
    within_reach: bool,
}

/// Points the projection turns into pixels side by side: arithmetic on arrays of this many,
/// with no branch in it, is what the compiler makes vector instructions of.
const LANES: usize = 8;

/// The camera as the projection uses it: base frame to pixels scaled by depth. Row `u` of
/// `rows` gives `u·z`, row `v` gives `v·z`, row `z` the depth along the optical axis, so whether
/// a point lands in the image is a comparison of products, and only a point that lands pays
/// for a division.
#[derive(Debug, Clone, Copy)]
struct Pinhole {
    /// The intrinsics times the base-to-optical rotation, a row each for u·z, v·z and z.
    rows: [[f32; 3]; 3],
    /// The intrinsics times the base-to-optical translation.
    offsets: [f32; 3],
    /// The image's width and height.
    right: f32,
    bottom: f32,
}

/// A group of points in the camera: their u·z, v·z and depth, and which of them land in the
/// image (bit `l` for lane `l`).
struct Lanes {
    uz: [f32; LANES],
    vz: [f32; LANES],
    z: [f32; LANES],
    lands: u32,
}

impl Pinhole {
    fn of(calibration: &CameraCalibration) -> Self {
        let camera_from_base = calibration.base_from_camera.inverse();
        let k = &calibration.intrinsics;
        let intrinsics = Matrix3::new(k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0);
        let rotation = intrinsics * camera_from_base.rotation.to_rotation_matrix().matrix();
        let translation: Vector3<f64> = intrinsics * camera_from_base.translation.vector;
        Self {
            rows: [0, 1, 2].map(|i| [0, 1, 2].map(|j| rotation[(i, j)] as f32)),
            offsets: [0, 1, 2].map(|i| translation[i] as f32),
            right: k.width as f32,
            bottom: k.height as f32,
        }
    }

    /// Where each of `group` lands. Every lane is computed and tested, landing or not, so the
    /// loops run without a branch; a point behind the camera or too near it (or NaN) lands
    /// nowhere.
    fn lanes(&self, group: &[Point3<f32>; LANES]) -> Lanes {
        let mut lanes = Lanes { uz: [0.0; LANES], vz: [0.0; LANES], z: [0.0; LANES], lands: 0 };
        let row = |i: usize, p: &Point3<f32>| {
            let r = &self.rows[i];
            r[0] * p.x + r[1] * p.y + r[2] * p.z + self.offsets[i]
        };
        for (l, p) in group.iter().enumerate() {
            lanes.uz[l] = row(0, p);
            lanes.vz[l] = row(1, p);
            lanes.z[l] = row(2, p);
        }
        for l in 0..LANES {
            let (uz, vz, z) = (lanes.uz[l], lanes.vz[l], lanes.z[l]);
            // NaN fails every comparison, so it lands nowhere.
            let lands = (z > 0.05)
                & (uz >= 0.0)
                & (uz < self.right * z)
                & (vz >= 0.0)
                & (vz < self.bottom * z);
            lanes.lands |= u32::from(lands) << l;
        }
        lanes
    }
}

impl ProjectedCloud {
    /// Projects `cloud` (base frame) into the camera of `calibration`, noting the pixels the
    /// points within `reach` land on.
    ///
    /// # Panics
    ///
    /// When the cloud holds more than `u32::MAX` points.
    pub fn new(
        cloud: &[Point3<f32>],
        calibration: &CameraCalibration,
        occlusion: &OcclusionTest,
        reach: &Reach,
    ) -> Self {
        assert!(u32::try_from(cloud.len()).is_ok(), "a cloud of over 4 billion points");
        let camera = Pinhole::of(calibration);
        // Asked of the points that land alone.
        let (centre, reach_squared) =
            (reach.centre.cast::<f32>(), (reach.radius * reach.radius) as f32);
        let within_reach = |p: &Point3<f32>| (p - centre).norm_squared() <= reach_squared;
        let k = &calibration.intrinsics;
        let (width, height) = (k.width as usize, k.height as usize);
        let cell = ((k.fx.max(k.fy) * occlusion.cell_angle).round() as usize).max(1);
        let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
        let (last_column, last_row) =
            ((width as u32).saturating_sub(1), (height as u32).saturating_sub(1));
        // A pixel's depth cell by table, column plus row: no division per point.
        let cell_column: Vec<u32> = (0..width).map(|x| (x / cell) as u32).collect();
        let cell_row: Vec<u32> = (0..height).map(|y| ((y / cell) * cols) as u32).collect();
        // The points are turned into pixels on every core, a block each (landings in the cloud's
        // order within a block); the depth cells and the seen pixels are then filled in that
        // same order on one, so the table is the one a single pass would have made.
        let landings: Vec<Vec<Landing>> = cloud
            .par_chunks(PROJECTION_BLOCK)
            .enumerate()
            .map(|(block, points)| {
                let first = block * PROJECTION_BLOCK;
                // Room for the whole block up front: growing by doubling copied it over again.
                // The ProjectedCloud lives for one look, and the pages never written are never
                // touched, so the room is not handed back.
                let mut landings = Vec::with_capacity(points.len());
                let mut lanes = points.chunks_exact(LANES);
                let mut land = |at: usize, group: &[Point3<f32>; LANES]| {
                    let at_camera = camera.lanes(group);
                    // The lanes that land, lowest first: most groups have none or all.
                    let mut lands = at_camera.lands;
                    while lands != 0 {
                        let l = lands.trailing_zeros() as usize;
                        lands &= lands - 1;
                        // Both lie in [0, size) with the size below 2^24: through u32 the pixel
                        // is the same, and the conversion needs none of the 64-bit saturation
                        // `as usize` costs. The products' test can pass a point whose division
                        // rounds up to the image's edge; it stays on the last column or row.
                        let z = at_camera.z[l];
                        let x = ((at_camera.uz[l] / z) as u32).min(last_column);
                        let y = ((at_camera.vz[l] / z) as u32).min(last_row);
                        let cell = cell_row[y as usize] + cell_column[x as usize];
                        let point = (first + at + l) as u32;
                        let within_reach = within_reach(&group[l]);
                        landings.push(Landing { point, x, y, cell, depth: z, within_reach });
                    }
                };
                for (g, group) in lanes.by_ref().enumerate() {
                    land(g * LANES, group.try_into().expect("chunks_exact"));
                }
                let rest = lanes.remainder();
                if !rest.is_empty() {
                    // The last few points, padded with NaN ones, which land nowhere.
                    let mut group = [Point3::from([f32::NAN; 3]); LANES];
                    group[..rest.len()].copy_from_slice(rest);
                    land(points.len() - rest.len(), &group);
                }
                landings
            })
            .collect();
        let mut nearest = vec![f32::INFINITY; cols * rows];
        let mut seen = Mask::new(width, height);
        for l in landings.iter().flatten() {
            let near = &mut nearest[l.cell as usize];
            *near = near.min(l.depth);
            if l.within_reach {
                seen.set(l.x as usize, l.y as usize, true);
            }
        }
        Self { width, height, points: cloud.len(), landings, nearest, seen }
    }

    /// The pixels some point of the cloud within the reach lands on.
    pub fn seen(&self) -> &Mask {
        &self.seen
    }

    /// The points of `cloud` (the cloud this was projected from) that land on set pixels of
    /// `mask` and are not hidden from the camera by nearer points.
    ///
    /// # Panics
    ///
    /// When `mask` is not the camera's size, or `cloud` not the size of the one projected.
    pub fn on_mask(
        &self,
        cloud: &[Point3<f32>],
        mask: &Mask,
        occlusion: &OcclusionTest,
    ) -> Vec<Point3<f32>> {
        assert_eq!((mask.width(), mask.height()), (self.width, self.height), "mask and camera");
        assert_eq!(cloud.len(), self.points, "the cloud projected");
        self.landings
            .iter()
            .flatten()
            .filter(|l| {
                mask.get(l.x as usize, l.y as usize)
                    && l.depth <= self.nearest[l.cell as usize] + occlusion.tolerance
            })
            .map(|l| cloud[l.point as usize])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hal::CameraIntrinsics;
    use nalgebra::{Isometry3, UnitQuaternion};

    /// A camera at the base origin looking along +x (optical z = base x, x = -y, y = -z).
    fn forward_camera() -> CameraCalibration {
        let rotation =
            UnitQuaternion::from_basis_unchecked(&[-Vector3::y(), -Vector3::z(), Vector3::x()]);
        CameraCalibration {
            intrinsics: CameraIntrinsics {
                width: 100,
                height: 100,
                fx: 100.0,
                fy: 100.0,
                cx: 50.0,
                cy: 50.0,
            },
            base_from_camera: Isometry3::from_parts(Vector3::zeros().into(), rotation),
        }
    }

    #[test]
    fn keeps_points_on_red_and_drops_the_hidden() {
        let mut mask = Mask::new(100, 100);
        for y in 40..60 {
            for x in 40..60 {
                mask.set(x, y, true);
            }
        }
        let cloud = vec![
            Point3::new(1.0, 0.0, 0.0),  // on red, nearest in its cell
            Point3::new(1.5, 0.0, 0.0),  // behind it, hidden from the camera
            Point3::new(1.0, 0.4, 0.0),  // left of the red patch
            Point3::new(-1.0, 0.0, 0.0), // behind the camera
        ];
        let kept = points_on_mask(&cloud, &mask, &forward_camera(), &OcclusionTest::default());
        assert_eq!(kept, vec![Point3::new(1.0, 0.0, 0.0)]);
    }

    #[test]
    fn points_land_on_the_pixels_the_camera_model_gives() {
        let camera = forward_camera();
        let everywhere = Reach { centre: Point3::origin(), radius: f64::INFINITY };
        // A fan of points across and beyond the picture, at depths from 0.3 m to 4 m, and the
        // picture's very edges, where a rounding could push a pixel out of the image.
        let mut cloud: Vec<Point3<f32>> = (0..4000)
            .map(|i| {
                let (a, b, d) = ((i % 97) as f32, (i % 89) as f32, (i % 37) as f32);
                let depth = 0.3 + d * 0.1;
                Point3::new(depth, depth * (a / 80.0 - 0.6), depth * (b / 70.0 - 0.6))
            })
            .collect();
        cloud.extend([
            Point3::new(1.0, 0.5, 0.5),
            Point3::new(1.0, -0.49999, -0.49999),
            Point3::new(1.0, 0.5, -0.49999),
        ]);
        let projected =
            ProjectedCloud::new(&cloud, &camera, &OcclusionTest::default(), &everywhere);
        let landed: Vec<&Landing> = projected.landings.iter().flatten().collect();
        let mut expected = 0;
        for (i, p) in cloud.iter().enumerate() {
            let k = &camera.intrinsics;
            let at = k.project(&(camera.base_from_camera.inverse() * p.cast::<f64>()));
            let inside = at.filter(|uv| {
                uv.x >= 0.0 && uv.y >= 0.0 && uv.x < k.width as f64 && uv.y < k.height as f64
            });
            let landing = landed.iter().find(|l| l.point as usize == i);
            // Within 1e-4 of a pixel's edge, relative to the coordinate (a hundredth of a pixel
            // at the far side of this image), single precision may round either way.
            let on_edge = at.is_some_and(|uv| {
                [uv.x, uv.y].iter().any(|c| (c - c.round()).abs() < 1e-4 * c.abs().max(1.0))
            });
            match (inside, landing) {
                (Some(uv), Some(l)) => {
                    expected += 1;
                    assert!(l.x < 100 && l.y < 100, "point {i} landed outside the image");
                    if !on_edge {
                        assert_eq!((l.x, l.y), (uv.x as u32, uv.y as u32), "point {i}");
                    }
                }
                (None, None) => {}
                (inside, landing) => assert!(on_edge, "point {i}: {inside:?} against {landing:?}"),
            }
        }
        assert!(expected > 1000, "only {expected} of the fan landed");
    }
}
