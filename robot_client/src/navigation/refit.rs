//! Refitting a RANSAC hypothesis to its inliers in narrowing bands, without rereading the whole
//! volume each time.
//!
//! Each refit takes the alive points within a band of the last plane. The points near the
//! hypothesis are gathered once, within a window wider than every band; a later plane's band can
//! only reach beyond them if the plane moved, somewhere in the points' bounding box, by more than
//! the window's slack. Distances from two planes differ by a linear function of the point, so
//! the largest move over the box is at one of its corners: when that is within the slack the
//! gathered points hold every inlier, in the same order, and the fit is the very one the whole
//! volume gives; otherwise the whole volume is read.

use nalgebra::Point3;

use super::plane::Plane;

/// The alive points near a hypothesis, and what it takes for them to hold a band's inliers.
pub(super) struct Refit<'a> {
    points: &'a [Point3<f32>],
    /// Every alive point, ascending, and those within `window` of `hypothesis`.
    alive: &'a [u32],
    near: Vec<u32>,
    hypothesis: Plane,
    window: f64,
    corners: [Point3<f64>; 8],
}

impl<'a> Refit<'a> {
    /// Gathers the `alive` points (indices into `points`, ascending) within `window` of
    /// `hypothesis`; `bounds` is the box all `points` lie in.
    pub(super) fn around(
        points: &'a [Point3<f32>],
        alive: &'a [u32],
        hypothesis: Plane,
        window: f64,
        bounds: &[Point3<f64>; 2],
    ) -> Self {
        // Room for every alive point up front: growing by doubling copied the gathered ones
        // over again, and this runs for every hypothesis judged.
        let mut near = Vec::with_capacity(alive.len());
        near.extend(
            alive
                .iter()
                .copied()
                .filter(|&i| hypothesis.signed_distance(&points[i as usize].cast()).abs() < window),
        );
        let [lo, hi] = bounds;
        let corners = std::array::from_fn(|c| {
            let pick = |bit: usize, lo: f64, hi: f64| if c >> bit & 1 == 1 { hi } else { lo };
            Point3::new(pick(0, lo.x, hi.x), pick(1, lo.y, hi.y), pick(2, lo.z, hi.z))
        });
        Self { points, alive, near, hypothesis, window, corners }
    }

    /// The alive points within `band` of `plane`, in ascending order.
    pub(super) fn within(&self, plane: &Plane, band: f64) -> impl Iterator<Item = u32> + '_ {
        let moved = self
            .corners
            .iter()
            .map(|c| (plane.signed_distance(c) - self.hypothesis.signed_distance(c)).abs())
            .fold(0.0, f64::max);
        // A margin far above rounding keeps the shortcut exact.
        let candidates = if moved + band + 1e-9 < self.window { &self.near } else { self.alive };
        let plane = *plane;
        candidates
            .iter()
            .copied()
            .filter(move |&i| plane.signed_distance(&self.points[i as usize].cast()).abs() < band)
    }

    /// The hypothesis refitted to its inliers within each of `bands` in turn.
    pub(super) fn refine(&self, bands: &[f64]) -> Plane {
        let mut refined = self.hypothesis;
        for &band in bands {
            let inliers = self.within(&refined, band).map(|i| self.points[i as usize].cast());
            if let Some((plane, _)) = Plane::fit(inliers) {
                refined = plane;
            }
        }
        refined
    }
}

/// The box `points` lie in.
pub(super) fn bounds(points: &[Point3<f32>]) -> [Point3<f64>; 2] {
    let (mut lo, mut hi) = (Point3::from([f64::INFINITY; 3]), Point3::from([f64::NEG_INFINITY; 3]));
    for p in points {
        let p: Point3<f64> = p.cast();
        (lo, hi) = (lo.inf(&p), hi.sup(&p));
    }
    [lo, hi]
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn the_near_points_answer_for_a_plane_that_moved_little_and_all_for_one_that_moved_much() {
        let points: Vec<Point3<f32>> = (0..2000)
            .map(|i| {
                let (a, b) = ((i % 40) as f32 * 0.025, (i / 40) as f32 * 0.02);
                Point3::new(2.0 + 0.02 * ((i * 7919) % 13) as f32 / 13.0 - 0.01, a, b)
            })
            .collect();
        let alive: Vec<u32> = (0..points.len() as u32).filter(|i| i % 3 != 0).collect();
        let wall = Plane { normal: -Vector3::x(), offset: 2.0 };
        let refit = Refit::around(&points, &alive, wall, 0.03, &bounds(&points));
        let everywhere = |plane: &Plane, band: f64| -> Vec<u32> {
            alive
                .iter()
                .copied()
                .filter(|&i| plane.signed_distance(&points[i as usize].cast()).abs() < band)
                .collect()
        };
        let tilted = Plane { normal: Vector3::new(-1.0, 0.003, 0.0).normalize(), offset: 2.001 };
        let turned = Plane { normal: Vector3::new(-1.0, 0.3, 0.0).normalize(), offset: 1.95 };
        for plane in [wall, tilted, turned] {
            for band in [0.015, 0.009] {
                assert_eq!(
                    refit.within(&plane, band).collect::<Vec<_>>(),
                    everywhere(&plane, band)
                );
            }
        }
    }
}
