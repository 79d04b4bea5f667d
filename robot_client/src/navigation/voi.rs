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
        let (cx, cy, cz) = (self.center.x as f32, self.center.y as f32, self.center.z as f32);
        let (dx, dy) = (p.x - cx, p.y - cy);
        dx * dx + dy * dy <= (self.radius * self.radius) as f32
            && p.z >= cz - self.below as f32
            && p.z <= cz + self.above as f32
    }

    /// The points of `cloud` inside the cylinder.
    pub fn crop(&self, cloud: &[Point3<f32>]) -> Vec<Point3<f32>> {
        // Room for every point up front: growing by doubling copied the cropped points over
        // and over, and the pages never written are never touched. The room left over is handed
        // back (in place, no copy), lest the plan that keeps these points keep a cloud's worth.
        let mut inside = Vec::with_capacity(cloud.len());
        inside.extend(cloud.iter().filter(|p| self.contains(p)));
        inside.shrink_to_fit();
        inside
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
}
