//! The paper's Fig. 5 as RViz markers: the volume of interest and its points cyan, the tag's
//! points red, the backing plane's dark green, the robot's body and extended arm at the
//! waypoint yellow-green, with an arrow for its heading.

use nalgebra::{Point3, UnitQuaternion, Vector3};
use pps_robot::navigation::{ApproachParams, ApproachPlan};

use crate::msg::builtin::{ColorRgba, Header};
use crate::msg::geometry::{Point, Pose, Vector3 as RosVector3};
use crate::msg::visualization::{Marker, MarkerArray};

const NAMESPACE: &str = "pps";
const CYAN: ColorRgba = ColorRgba { r: 0.0, g: 0.9, b: 0.9, a: 1.0 };
const RED: ColorRgba = ColorRgba { r: 1.0, g: 0.12, b: 0.12, a: 1.0 };
const DARK_GREEN: ColorRgba = ColorRgba { r: 0.0, g: 0.43, b: 0.12, a: 1.0 };
const YELLOW_GREEN: ColorRgba = ColorRgba { r: 0.67, g: 0.9, b: 0.16, a: 0.45 };
/// Drawn size of one laser point, metres.
const DOT: f64 = 0.008;

fn with_alpha(colour: ColorRgba, a: f32) -> ColorRgba {
    ColorRgba { a, ..colour }
}

fn marker(header: &Header, id: i32, kind: i32, colour: ColorRgba) -> Marker {
    Marker {
        header: header.clone(),
        ns: NAMESPACE.into(),
        id,
        kind,
        action: Marker::ADD,
        color: colour,
        scale: RosVector3 { x: DOT, y: DOT, z: DOT },
        ..Marker::default()
    }
}

fn dots(header: &Header, id: i32, colour: ColorRgba, points: &[Point3<f32>]) -> Marker {
    Marker {
        points: points.iter().map(|p| Point::from(p.cast::<f64>())).collect(),
        ..marker(header, id, Marker::POINTS, colour)
    }
}

fn cuboid(header: &Header, id: i32, centre: Point3<f64>, yaw: f64, size: [f64; 3]) -> Marker {
    Marker {
        pose: Pose::new(centre, UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw)),
        scale: RosVector3 { x: size[0], y: size[1], z: size[2] },
        ..marker(header, id, Marker::CUBE, YELLOW_GREEN)
    }
}

/// Every marker of one click; the first clears the previous click's.
pub fn fig5_markers(
    plan: &ApproachPlan,
    target: &Point3<f64>,
    params: &ApproachParams,
    header: &Header,
) -> MarkerArray {
    let mut markers = vec![Marker { action: Marker::DELETEALL, ..marker(header, 0, 0, CYAN) }];
    markers.push(Marker {
        pose: Pose::new(*target, UnitQuaternion::identity()),
        scale: RosVector3 {
            x: 2.0 * params.voi_radius,
            y: 2.0 * params.voi_radius,
            z: 2.0 * params.voi_half_height,
        },
        ..marker(header, 1, Marker::CYLINDER, with_alpha(CYAN, 0.12))
    });
    markers.push(dots(header, 2, CYAN, &plan.surface_points));
    if let Some(backing) = plan.backing_index.and_then(|i| plan.planes.get(i)) {
        let inliers: Vec<Point3<f32>> = backing
            .inliers
            .iter()
            .filter_map(|&i| plan.surface_points.get(i as usize).copied())
            .collect();
        markers.push(dots(header, 3, DARK_GREEN, &inliers));
    }
    if let Some(sighting) = &plan.tag {
        markers.push(dots(header, 4, RED, &sighting.nearest().members));
    }
    if let Some(w) = &plan.waypoint {
        let f = &params.footprint;
        let heading = Vector3::new(w.yaw.cos(), w.yaw.sin(), 0.0);
        let floor = Point3::new(w.position.x, w.position.y, 0.0);
        let body_height = f.height - f.floor_clearance;
        markers.push(cuboid(
            header,
            5,
            floor + Vector3::z() * (f.floor_clearance + body_height / 2.0),
            w.yaw,
            [2.0 * f.base_half_length, 2.0 * f.base_half_width, body_height],
        ));
        let arm_length = f.arm_reach - f.base_half_length;
        markers.push(cuboid(
            header,
            6,
            Point3::new(floor.x, floor.y, w.position.z)
                + heading * (f.base_half_length + arm_length / 2.0),
            w.yaw,
            [arm_length, 2.0 * f.arm_half_width, 2.0 * f.arm_half_height],
        ));
        markers.push(Marker {
            pose: Pose::new(floor, UnitQuaternion::from_axis_angle(&Vector3::z_axis(), w.yaw)),
            scale: RosVector3 { x: params.standoff, y: 0.04, z: 0.04 },
            ..marker(header, 7, Marker::ARROW, with_alpha(YELLOW_GREEN, 1.0))
        });
    }
    MarkerArray { markers }
}
