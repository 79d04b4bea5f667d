//! Analytic ray casting against the scene's primitive shapes, each in its own frame: the slab
//! test for boxes, a plane test for rectangles, the quadric for cylinders (with their caps) and
//! for the open cone frustum of a lamp shade.
//!
//! Every test returns the nearest hit beyond a small epsilon and before `t_max`, with the
//! surface's outward normal in the shape's frame (a rectangle's normal faces the ray, since a
//! rectangle has two sides; so does the frustum's, seen from inside).

use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// Hits nearer than this along a ray, metres, are the surface the ray starts on.
pub const T_MIN: f64 = 1e-6;

/// A half-line: `origin + t · direction`, `direction` a unit vector, `t` in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: Point3<f64>,
    pub direction: Vector3<f64>,
}

impl Ray {
    pub fn new(origin: Point3<f64>, direction: Vector3<f64>) -> Self {
        Self { origin, direction: direction.normalize() }
    }

    pub fn at(&self, t: f64) -> Point3<f64> {
        self.origin + self.direction * t
    }
}

/// A shape in its own frame, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Shape {
    /// A box centred on the origin with these half extents along x, y and z.
    Box { half_extents: [f64; 3] },
    /// A finite rectangle in the x–y plane centred on the origin, seen from both sides.
    Rectangle { half_size: [f64; 2] },
    /// A cylinder along z centred on the origin, closed by flat caps when `capped`.
    Cylinder { radius: f64, half_length: f64, capped: bool },
    /// An open cone frustum along z, radius `bottom_radius` at z = 0 and `top_radius` at
    /// z = `height`, seen from both sides: a lamp shade.
    Frustum { bottom_radius: f64, top_radius: f64, height: f64 },
}

/// Where a ray met a shape: distance along it and the surface normal, in the shape's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalHit {
    pub t: f64,
    pub normal: Vector3<f64>,
}

impl Shape {
    /// The nearest hit of the ray (`origin`, unit `direction`, shape frame) in (T_MIN, t_max).
    pub fn intersect(
        &self,
        origin: &Point3<f64>,
        direction: &Vector3<f64>,
        t_max: f64,
    ) -> Option<LocalHit> {
        match *self {
            Shape::Box { half_extents } => intersect_box(origin, direction, half_extents, t_max),
            Shape::Rectangle { half_size } => {
                intersect_rectangle(origin, direction, half_size, t_max)
            }
            Shape::Cylinder { radius, half_length, capped } => {
                intersect_cylinder(origin, direction, radius, half_length, capped, t_max)
            }
            Shape::Frustum { bottom_radius, top_radius, height } => {
                intersect_frustum(origin, direction, bottom_radius, top_radius, height, t_max)
            }
        }
    }

    /// The corners of a box holding the shape, in the shape frame, for culling.
    pub fn bounding_box(&self) -> [Point3<f64>; 8] {
        let (lo, hi) = match *self {
            Shape::Box { half_extents: [x, y, z] } => ([-x, -y, -z], [x, y, z]),
            Shape::Rectangle { half_size: [x, y] } => ([-x, -y, 0.0], [x, y, 0.0]),
            Shape::Cylinder { radius: r, half_length: h, .. } => ([-r, -r, -h], [r, r, h]),
            Shape::Frustum { bottom_radius, top_radius, height } => {
                let r = bottom_radius.max(top_radius);
                ([-r, -r, 0.0], [r, r, height])
            }
        };
        std::array::from_fn(|i| {
            let pick = |k: usize| if i >> k & 1 == 0 { lo[k] } else { hi[k] };
            Point3::new(pick(0), pick(1), pick(2))
        })
    }

    /// A sphere holding the shape (centre in the shape frame, radius), for culling.
    pub fn bounding_sphere(&self) -> (Point3<f64>, f64) {
        match *self {
            Shape::Box { half_extents: [x, y, z] } => {
                (Point3::origin(), (x * x + y * y + z * z).sqrt())
            }
            Shape::Rectangle { half_size: [x, y] } => (Point3::origin(), (x * x + y * y).sqrt()),
            Shape::Cylinder { radius, half_length, .. } => {
                (Point3::origin(), radius.hypot(half_length))
            }
            Shape::Frustum { bottom_radius, top_radius, height } => (
                Point3::new(0.0, 0.0, height / 2.0),
                bottom_radius.max(top_radius).hypot(height / 2.0),
            ),
        }
    }
}

/// The slab test: the ray's parameter interval inside each pair of faces, intersected.
fn intersect_box(
    o: &Point3<f64>,
    d: &Vector3<f64>,
    half: [f64; 3],
    t_max: f64,
) -> Option<LocalHit> {
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut near_axis, mut far_axis) = (0, 0);
    for k in 0..3 {
        if d[k].abs() < 1e-15 {
            if o[k].abs() > half[k] {
                return None;
            }
            continue;
        }
        let inv = 1.0 / d[k];
        let (a, b) = ((-half[k] - o[k]) * inv, (half[k] - o[k]) * inv);
        let (enter, exit) = if a < b { (a, b) } else { (b, a) };
        if enter > near {
            near = enter;
            near_axis = k;
        }
        if exit < far {
            far = exit;
            far_axis = k;
        }
        if near > far {
            return None;
        }
    }
    // Entering a face, the ray runs against its outward normal; leaving one, along it.
    let (t, axis, sign) = if near > T_MIN {
        (near, near_axis, -d[near_axis].signum())
    } else {
        (far, far_axis, d[far_axis].signum())
    };
    if t <= T_MIN || t >= t_max {
        return None;
    }
    let mut normal = Vector3::zeros();
    normal[axis] = sign;
    Some(LocalHit { t, normal })
}

fn intersect_rectangle(
    o: &Point3<f64>,
    d: &Vector3<f64>,
    [hx, hy]: [f64; 2],
    t_max: f64,
) -> Option<LocalHit> {
    if d.z.abs() < 1e-15 {
        return None;
    }
    let t = -o.z / d.z;
    if t <= T_MIN || t >= t_max {
        return None;
    }
    let (x, y) = (o.x + t * d.x, o.y + t * d.y);
    (x.abs() <= hx && y.abs() <= hy)
        .then(|| LocalHit { t, normal: Vector3::new(0.0, 0.0, -d.z.signum()) })
}

/// Roots of `a t² + 2 b t + c = 0` in increasing order, `None` when there are none.
fn quadratic_roots(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a.abs() < 1e-15 {
        if b.abs() < 1e-15 {
            return None;
        }
        let t = -c / (2.0 * b);
        return Some((t, t));
    }
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    // The stable form: no cancellation when b² ≫ a c.
    let q = -(b + b.signum() * disc.sqrt());
    let (t1, t2) = if q.abs() < 1e-300 { (0.0, 0.0) } else { (q / a, c / q) };
    Some(if t1 < t2 { (t1, t2) } else { (t2, t1) })
}

fn intersect_cylinder(
    o: &Point3<f64>,
    d: &Vector3<f64>,
    r: f64,
    h: f64,
    capped: bool,
    t_max: f64,
) -> Option<LocalHit> {
    let mut best: Option<LocalHit> = None;
    let mut consider = |t: f64, normal: Vector3<f64>| {
        if t > T_MIN && t < t_max && best.is_none_or(|b| t < b.t) {
            best = Some(LocalHit { t, normal });
        }
    };
    let a = d.x * d.x + d.y * d.y;
    let b = o.x * d.x + o.y * d.y;
    let c = o.x * o.x + o.y * o.y - r * r;
    if a > 1e-15
        && let Some((t1, t2)) = quadratic_roots(a, b, c)
    {
        for t in [t1, t2] {
            let p = o + d * t;
            if p.z.abs() <= h {
                consider(t, Vector3::new(p.x / r, p.y / r, 0.0));
            }
        }
    }
    if capped && d.z.abs() > 1e-15 {
        for (z, nz) in [(h, 1.0), (-h, -1.0)] {
            let t = (z - o.z) / d.z;
            let p = o + d * t;
            if p.x * p.x + p.y * p.y <= r * r {
                consider(t, Vector3::new(0.0, 0.0, nz));
            }
        }
    }
    best
}

fn intersect_frustum(
    o: &Point3<f64>,
    d: &Vector3<f64>,
    r0: f64,
    r1: f64,
    height: f64,
    t_max: f64,
) -> Option<LocalHit> {
    // x² + y² = (r0 + k z)² for 0 ≤ z ≤ height.
    let k = (r1 - r0) / height;
    let radius_at_o = r0 + k * o.z;
    let a = d.x * d.x + d.y * d.y - k * k * d.z * d.z;
    let b = o.x * d.x + o.y * d.y - k * radius_at_o * d.z;
    let c = o.x * o.x + o.y * o.y - radius_at_o * radius_at_o;
    let (t1, t2) = quadratic_roots(a, b, c)?;
    [t1, t2].into_iter().find_map(|t| {
        if t <= T_MIN || t >= t_max {
            return None;
        }
        let p = o + d * t;
        let radius = r0 + k * p.z;
        (p.z >= 0.0 && p.z <= height && radius >= 0.0).then(|| {
            // At the apex the gradient vanishes; the axis stands in.
            let normal =
                Vector3::new(p.x, p.y, -k * radius).try_normalize(1e-12).unwrap_or(Vector3::z());
            LocalHit { t, normal }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(shape: Shape, origin: [f64; 3], direction: [f64; 3]) -> Option<LocalHit> {
        let d = Vector3::from(direction).normalize();
        shape.intersect(&Point3::from(origin), &d, 100.0)
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn a_box_is_entered_through_the_face_the_ray_meets_first() {
        let b = Shape::Box { half_extents: [1.0, 2.0, 3.0] };
        let h = hit(b, [-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!(close(h.t, 4.0) && h.normal == Vector3::new(-1.0, 0.0, 0.0));
        // Diagonal from above: enters the top face z = 3 at (0.5, 0.5, 3), t = 2·√3.
        let h = hit(b, [-1.5, -1.5, 5.0], [1.0, 1.0, -1.0]).unwrap();
        assert!(close(h.t, 2.0 * 3f64.sqrt()), "{}", h.t);
        assert_eq!(h.normal, Vector3::new(0.0, 0.0, 1.0));
        // Parallel to a slab and outside it.
        assert!(hit(b, [-5.0, 2.5, 0.0], [1.0, 0.0, 0.0]).is_none());
        // From inside, the exit face.
        let h = hit(b, [0.0, 0.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!(close(h.t, 2.0) && h.normal == Vector3::new(0.0, -1.0, 0.0));
        // Pointing away.
        assert!(hit(b, [-5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn a_rectangle_has_two_sides_and_edges() {
        let r = Shape::Rectangle { half_size: [1.0, 0.5] };
        let h = hit(r, [0.2, 0.1, 2.0], [0.0, 0.0, -1.0]).unwrap();
        assert!(close(h.t, 2.0) && h.normal.z == 1.0);
        let h = hit(r, [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]).unwrap();
        assert!(close(h.t, 3.0) && h.normal.z == -1.0);
        assert!(hit(r, [0.0, 0.6, 2.0], [0.0, 0.0, -1.0]).is_none(), "beyond the half size");
        // At 45°: from (−2, 0, 2) to (0, 0, 0), t = 2√2.
        let h = hit(r, [-2.0, 0.0, 2.0], [1.0, 0.0, -1.0]).unwrap();
        assert!(close(h.t, 2.0 * 2f64.sqrt()));
    }

    #[test]
    fn a_cylinder_is_hit_on_its_side_or_its_caps() {
        let c = Shape::Cylinder { radius: 1.0, half_length: 2.0, capped: true };
        let h = hit(c, [-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!(close(h.t, 2.0) && (h.normal - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-12);
        // Off axis by 0.6: meets x = −0.8.
        let h = hit(c, [-3.0, 0.6, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!(close(h.t, 2.2), "{}", h.t);
        assert!((h.normal - Vector3::new(-0.8, 0.6, 0.0)).norm() < 1e-12);
        let h = hit(c, [0.5, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
        assert!(close(h.t, 3.0) && h.normal.z == 1.0);
        // Without caps, a ray down the inside along the axis meets nothing.
        let open = Shape::Cylinder { radius: 1.0, half_length: 2.0, capped: false };
        assert!(hit(open, [0.5, 0.0, 5.0], [0.0, 0.0, -1.0]).is_none());
        // Above the side's end.
        assert!(hit(c, [-3.0, 0.0, 2.5], [1.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn a_frustum_is_a_slanted_open_surface() {
        // A cone of radius 1 at z = 0 narrowing to a point at z = 1.
        let f = Shape::Frustum { bottom_radius: 1.0, top_radius: 0.0, height: 1.0 };
        let h = hit(f, [-3.0, 0.0, 0.5], [1.0, 0.0, 0.0]).unwrap();
        assert!(close(h.t, 2.5), "{}", h.t);
        let expected = Vector3::new(-1.0, 0.0, 1.0).normalize();
        assert!((h.normal - expected).norm() < 1e-12, "{:?}", h.normal);
        // Through the open bottom, it meets the inside of the surface.
        let h = hit(f, [0.0, 0.0, -1.0], [0.0, 0.0, 1.0]).unwrap();
        assert!(close(h.t, 2.0), "the apex, {}", h.t);
        // A shade radius 0.2 → 0.1 over 0.25 m, seen level at z = 0.125: radius 0.15.
        let shade = Shape::Frustum { bottom_radius: 0.2, top_radius: 0.1, height: 0.25 };
        let h = hit(shade, [-1.0, 0.0, 0.125], [1.0, 0.0, 0.0]).unwrap();
        assert!(close(h.t, 0.85), "{}", h.t);
        assert!(hit(shade, [-1.0, 0.0, 0.3], [1.0, 0.0, 0.0]).is_none(), "above the rim");
    }

    #[test]
    fn bounding_spheres_hold_their_shapes() {
        let shapes = [
            Shape::Box { half_extents: [0.3, 0.2, 0.1] },
            Shape::Rectangle { half_size: [1.0, 2.0] },
            Shape::Cylinder { radius: 0.1, half_length: 0.5, capped: true },
            Shape::Frustum { bottom_radius: 0.2, top_radius: 0.1, height: 0.3 },
        ];
        for shape in shapes {
            let (c, r) = shape.bounding_sphere();
            // Rays from all around toward the centre hit the shape no further in than the sphere.
            for i in 0..64 {
                let a = i as f64 * 0.7;
                let dir = Vector3::new(a.cos() * (a * 0.3).sin(), a.sin(), (a * 0.3).cos());
                let origin = c + dir.normalize() * (r + 1.0);
                if let Some(h) = shape.intersect(&origin, &-dir.normalize(), 100.0) {
                    assert!(h.t >= 1.0 - 1e-9, "{shape:?} hit inside its sphere's shell");
                }
            }
        }
    }
}
