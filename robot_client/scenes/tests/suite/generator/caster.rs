//! The ray caster against hits computed by hand.

use nalgebra::{Isometry3, Point3, Vector3};
use pps_scenes::caster::RayCaster;
use pps_scenes::geometry::{Ray, Shape};
use pps_scenes::materials;
use pps_scenes::scene::{Primitive, Scene};

use super::dark;

#[test]
fn the_caster_meets_shapes_where_hand_geometry_says() {
    let scene = Scene {
        primitives: vec![
            // A cabinet front: a box 0.4 m deep whose face is at x = 1.5.
            Primitive::new(
                "box",
                Shape::Box { half_extents: [0.2, 0.3, 0.4] },
                Isometry3::translation(1.7, 0.0, 0.5),
                materials::FURNITURE[1],
            ),
            // A pole standing at (1.0, 0.6), radius 2 cm.
            Primitive::new(
                "pole",
                Shape::Cylinder { radius: 0.02, half_length: 0.75, capped: true },
                Isometry3::translation(1.0, 0.6, 0.75),
                materials::CHROME,
            ),
            // The floor.
            Primitive::new(
                "floor",
                Shape::Rectangle { half_size: [5.0, 5.0] },
                Isometry3::identity(),
                materials::FLOORS[0],
            ),
        ],
        lights: dark(),
    };
    let caster = RayCaster::new(&scene);
    let all = caster.all();
    let from = Point3::new(0.0, 0.0, 0.5);
    let hit = caster.cast(&Ray::new(from, Vector3::x()), &all, 10.0).unwrap();
    assert_eq!(hit.primitive, 0);
    assert!((hit.t - 1.5).abs() < 1e-9 && (hit.normal + Vector3::x()).norm() < 1e-9);
    // 45° down from 0.5 m: the floor at 0.5 m ahead, t = 0.5·√2.
    let hit = caster.cast(&Ray::new(from, Vector3::new(1.0, 0.0, -1.0)), &all, 10.0).unwrap();
    assert_eq!(hit.primitive, 2);
    assert!((hit.t - 0.5 * 2f64.sqrt()).abs() < 1e-9 && hit.normal.z > 0.999);
    // Toward the pole's axis: its surface 2 cm short of the axis.
    let to_pole = Vector3::new(1.0, 0.6, 0.0);
    let hit = caster.cast(&Ray::new(from, to_pole), &all, 10.0).unwrap();
    assert_eq!(hit.primitive, 1);
    assert!((hit.t - (to_pole.norm() - 0.02)).abs() < 1e-9, "{}", hit.t);
    // The box's top edge: a ray just over it reaches the floor far behind.
    let over = Vector3::new(1.5, 0.0, 0.4 + 0.001);
    let hit = caster.cast(&Ray::new(from, over), &all, 10.0);
    assert!(hit.is_none(), "above the box and the floor is below: nothing, got {hit:?}");
}
