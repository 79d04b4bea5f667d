//! What the devices are built of: boxes between two corners, rods along an axis, the extent
//! of a box, and a finish picked from a palette.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::Rng;

use super::Extent;
use crate::geometry::Shape;
use crate::materials::Material;
use crate::scene::Primitive;

pub(super) fn pick<T: Copy>(palette: &[T], rng: &mut impl Rng) -> T {
    palette[rng.random_range(0..palette.len())]
}

/// An axis-aligned box between two corners.
pub(super) fn slab(name: &str, a: [f64; 3], b: [f64; 3], material: Material) -> Primitive {
    let center = Vector3::new((a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0);
    let half = [(b[0] - a[0]).abs() / 2.0, (b[1] - a[1]).abs() / 2.0, (b[2] - a[2]).abs() / 2.0];
    Primitive::new(name, Shape::Box { half_extents: half }, Isometry3::from(center), material)
}

/// A cylinder with its axis along `axis` through `center`.
pub(super) fn rod(
    name: &str,
    center: Point3<f64>,
    axis: Vector3<f64>,
    radius: f64,
    length: f64,
    material: Material,
) -> Primitive {
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    Primitive::new(
        name,
        Shape::Cylinder { radius, half_length: length / 2.0, capped: true },
        Isometry3::from_parts(Translation3::from(center.coords), rotation),
        material,
    )
}

pub(super) fn extent_of(a: [f64; 3], b: [f64; 3]) -> Extent {
    Extent {
        min: Point3::new(a[0].min(b[0]), a[1].min(b[1]), a[2].min(b[2])),
        max: Point3::new(a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])),
    }
}
