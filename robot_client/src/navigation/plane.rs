//! Planes: through three points, fitted to many, and where a point lies relative to one.

use nalgebra::{Matrix3, Point3, SymmetricEigen, Vector3};

/// The plane `normal · p + offset = 0`, `normal` a unit vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub normal: Vector3<f64>,
    pub offset: f64,
}

impl Plane {
    /// The plane through three points, or `None` when they are (nearly) collinear.
    pub fn through(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> Option<Self> {
        let n = (b - a).cross(&(c - a));
        let norm = n.norm();
        // Less than ~1 cm² of triangle: the points lie along a scan line.
        if norm < 1e-4 {
            return None;
        }
        let normal = n / norm;
        Some(Self { normal, offset: -normal.dot(&a.coords) })
    }

    /// Least-squares plane through `points` (the smallest principal axis of their scatter) and
    /// their centroid; `None` for fewer than three points.
    pub fn fit(points: impl Iterator<Item = Point3<f64>>) -> Option<(Self, Point3<f64>)> {
        let (mut n, mut sum) = (0usize, Vector3::zeros());
        // The sums of products of coordinates: the scatter matrix is symmetric and x·y is y·x
        // to the last bit, so its upper triangle alone gives the very matrix, in two thirds of
        // the arithmetic (the plane search fits tens of thousands of points a scene).
        let [mut xx, mut xy, mut xz, mut yy, mut yz, mut zz] = [0.0; 6];
        for p in points {
            n += 1;
            sum += p.coords;
            let (x, y, z) = (p.x, p.y, p.z);
            (xx, xy, xz) = (xx + x * x, xy + x * y, xz + x * z);
            (yy, yz, zz) = (yy + y * y, yz + y * z, zz + z * z);
        }
        if n < 3 {
            return None;
        }
        let outer = Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        let mean = sum / n as f64;
        let covariance = outer / n as f64 - mean * mean.transpose();
        let eigen = SymmetricEigen::new(covariance);
        let smallest = eigen.eigenvalues.imin();
        let normal = eigen.eigenvectors.column(smallest).into_owned().normalize();
        Some((Self { normal, offset: -normal.dot(&mean) }, Point3::from(mean)))
    }

    /// Signed distance of `p` from the plane, positive on the side the normal points to.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        self.normal.dot(&p.coords) + self.offset
    }

    /// The same plane with its normal pointing toward `viewpoint`.
    pub fn facing(self, viewpoint: &Point3<f64>) -> Self {
        if self.signed_distance(viewpoint) < 0.0 {
            Self { normal: -self.normal, offset: -self.offset }
        } else {
            self
        }
    }

    /// Two unit vectors spanning the plane: the first horizontal when the plane is not.
    pub fn basis(&self) -> (Vector3<f64>, Vector3<f64>) {
        let across = self.normal.cross(&Vector3::z());
        let u = if across.norm() > 1e-3 { across.normalize() } else { Vector3::x() };
        (u, self.normal.cross(&u))
    }

    /// Angle between the normal and the horizontal, radians: 0 for a wall, π/2 for a floor.
    pub fn tilt_from_vertical(&self) -> f64 {
        self.normal.z.abs().clamp(0.0, 1.0).asin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn fit_recovers_random_planes() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..100 {
            let normal = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize();
            let offset = rng.random_range(-2.0..2.0);
            let plane = Plane { normal, offset };
            let (u, v) = plane.basis();
            let origin = Point3::from(-normal * offset);
            let points: Vec<_> = (0..200)
                .map(|_| {
                    origin
                        + u * rng.random_range(-0.5..0.5)
                        + v * rng.random_range(-0.5..0.5)
                        + normal * rng.random_range(-0.003..0.003)
                })
                .collect();
            let (fitted, _) = Plane::fit(points.iter().copied()).unwrap();
            assert!(fitted.normal.dot(&normal).abs() > 0.999);
            for p in &points {
                assert!(fitted.signed_distance(p).abs() < 0.01);
            }
            let through = Plane::through(&points[0], &points[1], &points[2]).unwrap();
            assert!(through.signed_distance(&points[2]).abs() < 1e-9);
            let facing = plane.facing(&Point3::new(5.0, 5.0, 5.0));
            assert!(facing.signed_distance(&Point3::new(5.0, 5.0, 5.0)) > 0.0);
        }
        assert!(
            Plane::through(
                &Point3::origin(),
                &Point3::new(1.0, 0.0, 0.0),
                &Point3::new(2.0, 0.0, 0.0)
            )
            .is_none()
        );
    }
}
