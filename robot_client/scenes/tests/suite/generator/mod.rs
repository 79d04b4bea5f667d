//! The scene source itself: its ray caster against hand-computed hits, its laser's noise growing
//! with range and incidence, its mixed pixels and dropouts, the tag's colour in the camera
//! under bright and dim light, the ground truth, and the corpus's spread over issue 11's space.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pps_scenes::geometry::Shape;
use pps_scenes::lighting::Lights;
use pps_scenes::materials;
use pps_scenes::scene::Primitive;

mod camera;
mod caster;
mod draw;
mod laser;

/// No light but what a test adds: the laser needs none, and the caster test wants none.
fn dark() -> Lights {
    Lights { ambient: [0.0; 3], room: vec![], flash: None }
}

/// A wall facing the origin `distance` metres away, its normal turned `incidence` radians about z.
fn wall(distance: f64, incidence: f64) -> Primitive {
    let facing = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), incidence)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    Primitive::new(
        "wall",
        Shape::Rectangle { half_size: [3.0, 6.0] },
        Isometry3::from_parts(Translation3::new(distance, 0.0, 1.0), facing),
        materials::WALLS[0],
    )
}
