//! A scene made ready for casting: every primitive's pose as a matrix, its bounding sphere in the
//! base frame, and a cull that keeps, for a bundle of rays leaving one point inside a cone (a
//! tile of pixels, a run of laser beams), only the primitives whose spheres the cone reaches.

use nalgebra::{Matrix3, Point3, Vector3};

use crate::geometry::{Ray, Shape};
use crate::materials::Material;
use crate::scene::Scene;

/// Where a ray met the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Distance along the ray, metres.
    pub t: f64,
    pub point: Point3<f64>,
    /// Unit surface normal, base frame, on the side the ray came from.
    pub normal: Vector3<f64>,
    /// Index of the primitive in the scene.
    pub primitive: u32,
}

#[derive(Debug, Clone)]
struct Prepared {
    /// Base frame from the shape's frame.
    rotation: Matrix3<f64>,
    translation: Vector3<f64>,
    shape: Shape,
    center: Point3<f64>,
    radius: f64,
    /// Corners of its bounding box, base frame.
    corners: [Point3<f64>; 8],
}

/// The scene's primitives, ready for rays.
#[derive(Debug, Clone)]
pub struct RayCaster {
    items: Vec<Prepared>,
    materials: Vec<Material>,
}

impl RayCaster {
    pub fn new(scene: &Scene) -> Self {
        let items = scene
            .primitives
            .iter()
            .map(|p| {
                let iso = p.pose.isometry();
                let (local_center, radius) = p.shape.bounding_sphere();
                Prepared {
                    rotation: *iso.rotation.to_rotation_matrix().matrix(),
                    translation: iso.translation.vector,
                    shape: p.shape,
                    center: iso * local_center,
                    radius,
                    corners: p.shape.bounding_box().map(|c| iso * c),
                }
            })
            .collect();
        Self { items, materials: scene.primitives.iter().map(|p| p.material).collect() }
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    pub fn material(&self, primitive: u32) -> &Material {
        &self.materials[primitive as usize]
    }

    /// The corners of primitive `i`'s bounding box, base frame.
    pub fn corners(&self, primitive: u32) -> &[Point3<f64>; 8] {
        &self.items[primitive as usize].corners
    }

    /// How far from `from` primitive `i`'s bounding sphere begins, metres (negative inside it).
    pub fn sphere_distance(&self, primitive: u32, from: &Point3<f64>) -> f64 {
        let item = &self.items[primitive as usize];
        (item.center - from).norm() - item.radius
    }

    /// Every primitive, for a ray with no cull.
    pub fn all(&self) -> Vec<u32> {
        (0..self.items.len() as u32).collect()
    }

    /// The primitives a ray from `apex` within `half_angle` (radians) of the unit `axis` may
    /// meet, into `out` (cleared first), nearest bounding sphere first so that [`Self::cast`]
    /// can skip the rest once it has a hit.
    pub fn cull_cone(
        &self,
        apex: &Point3<f64>,
        axis: &Vector3<f64>,
        half_angle: f64,
        out: &mut Vec<u32>,
    ) {
        out.clear();
        let mut near = Vec::with_capacity(self.items.len());
        for (i, item) in self.items.iter().enumerate() {
            let to_center = item.center - apex;
            let distance = to_center.norm();
            let keep = distance <= item.radius || {
                let off_axis = (axis.dot(&to_center) / distance).clamp(-1.0, 1.0).acos();
                off_axis <= half_angle + (item.radius / distance).asin()
            };
            if keep {
                near.push((distance - item.radius, i as u32));
            }
        }
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        out.extend(near.into_iter().map(|(_, i)| i));
    }

    /// The nearest hit of `ray` among `candidates` before `t_max` metres.
    pub fn cast(&self, ray: &Ray, candidates: &[u32], t_max: f64) -> Option<Hit> {
        let mut best: Option<(f64, Vector3<f64>, u32)> = None;
        let mut limit = t_max;
        for &i in candidates {
            let item = &self.items[i as usize];
            // Skip shapes whose bounding sphere lies wholly beyond the best hit so far.
            let along = (item.center - ray.origin).dot(&ray.direction);
            if along - item.radius > limit {
                continue;
            }
            let origin =
                Point3::from(item.rotation.tr_mul(&(ray.origin.coords - item.translation)));
            let direction = item.rotation.tr_mul(&ray.direction);
            if let Some(hit) = item.shape.intersect(&origin, &direction, limit) {
                limit = hit.t;
                best = Some((hit.t, item.rotation * hit.normal, i));
            }
        }
        best.map(|(t, normal, primitive)| {
            let normal = if normal.dot(&ray.direction) > 0.0 { -normal } else { normal };
            Hit { t, point: ray.at(t), normal, primitive }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lighting::Lights;
    use crate::materials::WALLS;
    use crate::scene::Primitive;
    use nalgebra::{Isometry3, UnitQuaternion};

    fn scene(primitives: Vec<Primitive>) -> Scene {
        Scene { primitives, lights: Lights { ambient: [0.1; 3], room: vec![], flash: None } }
    }

    #[test]
    fn a_posed_box_is_hit_where_its_rotated_face_is() {
        // A 0.2 × 0.4 × 0.6 box at (2, 0, 1), turned 90° about z: its 0.4 m side now runs along x.
        let pose = Isometry3::from_parts(
            Vector3::new(2.0, 0.0, 1.0).into(),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2),
        );
        let b = Primitive::new("box", Shape::Box { half_extents: [0.1, 0.2, 0.3] }, pose, WALLS[0]);
        let caster = RayCaster::new(&scene(vec![b]));
        let ray = Ray::new(Point3::new(0.0, 0.0, 1.0), Vector3::x());
        let hit = caster.cast(&ray, &caster.all(), 10.0).unwrap();
        assert!((hit.t - 1.8).abs() < 1e-9, "{}", hit.t);
        assert!((hit.normal - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-9);
        // Across y it is 0.2 wide: a ray at y = 0.15 misses.
        let ray = Ray::new(Point3::new(0.0, 0.15, 1.0), Vector3::x());
        assert!(caster.cast(&ray, &caster.all(), 10.0).is_none());
    }

    #[test]
    fn the_nearest_of_several_primitives_wins_and_the_cull_keeps_it() {
        let wall = Primitive::new(
            "wall",
            Shape::Rectangle { half_size: [1.0, 1.0] },
            Isometry3::from_parts(
                Vector3::new(3.0, 0.0, 1.0).into(),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
            ),
            WALLS[0],
        );
        let post = Primitive::new(
            "post",
            Shape::Cylinder { radius: 0.1, half_length: 0.5, capped: true },
            Isometry3::translation(2.0, 0.0, 1.0),
            WALLS[1],
        );
        let far_away = Primitive::new(
            "far",
            Shape::Box { half_extents: [0.1; 3] },
            Isometry3::translation(0.0, 5.0, 1.0),
            WALLS[2],
        );
        let caster = RayCaster::new(&scene(vec![wall, post, far_away]));
        let origin = Point3::new(0.0, 0.0, 1.0);
        let mut kept = Vec::new();
        caster.cull_cone(&origin, &Vector3::x(), 0.05, &mut kept);
        assert_eq!(kept, vec![1, 0], "the box off to the side is culled, the post comes first");
        let hit = caster.cast(&Ray::new(origin, Vector3::x()), &kept, 10.0).unwrap();
        assert_eq!(hit.primitive, 1);
        assert!((hit.t - 1.9).abs() < 1e-9);
        // Just past the post, the wall; its normal faces the ray.
        let ray = Ray::new(origin, Vector3::new(3.0, 0.15 * 1.5, 0.0));
        let hit = caster.cast(&ray, &kept, 10.0).unwrap();
        assert_eq!(hit.primitive, 0);
        assert!((hit.point.x - 3.0).abs() < 1e-9 && hit.normal.x < -0.999);
    }
}
