//! The cylindrical volume of interest around the target (paper §IV-B.1.a: "the axis of the
//! cylinder is parallel to gravity and passes through the selected location").

use nalgebra::Point3;

/// A vertical cylinder around a point, base frame (z is up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolumeOfInterest {
    pub center: Point3<f64>,
    /// Radius, metres.
    pub radius: f64,
    /// How far the cylinder reaches below and above the centre, metres.
    pub below: f64,
    pub above: f64,
}

impl VolumeOfInterest {
    /// A cylinder of `radius` reaching `half_height` above and below `center`.
    pub fn around(center: Point3<f64>, radius: f64, half_height: f64) -> Self {
        Self { center, radius, below: half_height, above: half_height }
    }

    pub fn contains(&self, p: &Point3<f32>) -> bool {
        Bounds::of(self).hold(p)
    }

    /// The points of `cloud` inside the cylinder.
    pub fn crop(&self, cloud: &[Point3<f32>]) -> Vec<Point3<f32>> {
        let bounds = Bounds::of(self);
        // Room for every point up front: growing by doubling copied the cropped points over
        // and over, and the pages never written are never touched. The room left over is handed
        // back (in place, no copy), lest the plan that keeps these points keep a cloud's worth.
        let mut inside = Vec::with_capacity(cloud.len());
        // Eight points tested at a time without a branch (vector instructions), then the ones
        // inside kept in order: a branch a point mispredicted at every edge of the cylinder,
        // and this reads the whole cloud beside the tag search.
        let mut groups = cloud.chunks_exact(LANES);
        for group in groups.by_ref() {
            let mut lanes = group
                .iter()
                .enumerate()
                .fold(0u32, |lanes, (l, p)| lanes | u32::from(bounds.hold(p)) << l);
            while lanes != 0 {
                inside.push(group[lanes.trailing_zeros() as usize]);
                lanes &= lanes - 1;
            }
        }
        inside.extend(groups.remainder().iter().filter(|p| bounds.hold(p)));
        inside.shrink_to_fit();
        inside
    }
}

/// Points the crop tests side by side.
const LANES: usize = 8;

/// The cylinder in the cloud's single precision, converted once rather than for every point.
struct Bounds {
    x: f32,
    y: f32,
    radius_squared: f32,
    bottom: f32,
    top: f32,
}

impl Bounds {
    fn of(voi: &VolumeOfInterest) -> Self {
        let c = &voi.center;
        Self {
            x: c.x as f32,
            y: c.y as f32,
            radius_squared: (voi.radius * voi.radius) as f32,
            bottom: c.z as f32 - voi.below as f32,
            top: c.z as f32 + voi.above as f32,
        }
    }

    /// Every comparison made (`&`, not `&&`), so that testing a point has no branch.
    fn hold(&self, p: &Point3<f32>) -> bool {
        let (dx, dy) = (p.x - self.x, p.y - self.y);
        (dx * dx + dy * dy <= self.radius_squared) & (p.z >= self.bottom) & (p.z <= self.top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_axis_is_vertical() {
        let voi = VolumeOfInterest::around(Point3::new(1.0, 0.0, 1.0), 0.5, 0.5);
        assert!(voi.contains(&Point3::new(1.4, 0.2, 1.49)));
        assert!(!voi.contains(&Point3::new(1.4, 0.4, 1.0)), "outside the radius");
        assert!(!voi.contains(&Point3::new(1.0, 0.0, 1.6)), "above the top");
        assert_eq!(voi.crop(&[Point3::new(1.0, 0.0, 0.6), Point3::new(0.0, 0.0, 1.0)]).len(), 1);
    }

    #[test]
    fn the_crop_keeps_the_points_inside_in_order() {
        let voi = VolumeOfInterest::around(Point3::new(1.0, 0.0, 1.0), 0.5, 0.5);
        // Groups of eight and a remainder, inside and outside interleaved.
        let cloud: Vec<Point3<f32>> = (0..27)
            .map(|i| {
                Point3::new(0.4 + 0.05 * i as f32, 0.1 * (i % 3) as f32, 0.4 + 0.03 * i as f32)
            })
            .collect();
        let expected: Vec<Point3<f32>> =
            cloud.iter().copied().filter(|p| voi.contains(p)).collect();
        assert!(!expected.is_empty() && expected.len() < cloud.len());
        assert_eq!(voi.crop(&cloud), expected);
    }
}
