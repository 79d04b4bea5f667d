//! The approach waypoint (paper §IV-B.1.a: "a waypoint 50 cm from the selected tag in the
//! direction perpendicular to the plane") and the check that the robot fits there.

use nalgebra::{Point3, Vector3};
use rayon::prelude::*;

use super::backing_plane::BackingPlane;

/// Points a core checks at a time: the test is a few comparisons for most points, so blocks
/// twice the projection's keep the split's bookkeeping small beside them.
const CLEARANCE_BLOCK: usize = 8192;

/// Where the base should stand and which way it should face, base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ApproachWaypoint {
    /// `standoff` metres out from the tag along the plane's horizontal normal, at the tag's
    /// height: the base centres itself under this point.
    pub position: Point3<f64>,
    /// Heading that faces the tag, radians (0 is the base's +x, counter-clockwise positive).
    pub yaw: f64,
}

/// The waypoint `standoff` metres out from `tag` along the plane's normal; `None` when the plane
/// is horizontal and has no direction to approach along.
pub fn approach_waypoint(
    tag: &Point3<f64>,
    plane: &BackingPlane,
    standoff: f64,
) -> Option<ApproachWaypoint> {
    let out = Vector3::new(plane.normal.x, plane.normal.y, 0.0).try_normalize(1e-6)?;
    Some(ApproachWaypoint { position: tag + out * standoff, yaw: (-out.y).atan2(-out.x) })
}

/// The robot's body as boxes for the collision check: the base and the arm extended forward.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotFootprint {
    /// Half length (along the heading) and half width of the base, metres.
    pub base_half_length: f64,
    pub base_half_width: f64,
    /// The body's height, metres; points below `floor_clearance` are the floor.
    pub height: f64,
    pub floor_clearance: f64,
    /// How far ahead of the base's centre the extended hand reaches, metres.
    pub arm_reach: f64,
    /// Half width and half height of the arm and hand, metres.
    pub arm_half_width: f64,
    pub arm_half_height: f64,
    /// Points inside the boxes that still count as clear (the laser's stray returns).
    pub tolerated_points: usize,
}

impl Default for RobotFootprint {
    /// EL-E-like: a 50 cm square base, the hand stopping 12 cm short of a tag 50 cm ahead.
    fn default() -> Self {
        Self {
            base_half_length: 0.25,
            base_half_width: 0.25,
            height: 1.6,
            floor_clearance: 0.04,
            arm_reach: 0.38,
            arm_half_width: 0.06,
            arm_half_height: 0.06,
            tolerated_points: 4,
        }
    }
}

impl RobotFootprint {
    /// How far any of the boxes reaches from the waypoint, metres, and a centimetre more (far
    /// beyond rounding).
    pub fn reach(&self) -> f64 {
        self.base_half_length
            .hypot(self.base_half_width)
            .max(self.arm_reach.max(self.base_half_length).hypot(self.arm_half_width))
            + 0.01
    }
}

/// Whether the robot fits at the waypoint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clearance {
    Clear,
    /// `points` points lie inside the robot's boxes; `nearest` is the one nearest the base's centre.
    Blocked {
        points: usize,
        nearest: Point3<f64>,
    },
}

/// Checks the base and the extended arm, held at `hand_height`, against `cloud` (base frame)
/// with the robot at `waypoint`.
pub fn check_clearance(
    cloud: &[Point3<f32>],
    waypoint: &ApproachWaypoint,
    hand_height: f64,
    footprint: &RobotFootprint,
) -> Clearance {
    let (sin, cos) = waypoint.yaw.sin_cos();
    let (wx, wy) = (waypoint.position.x, waypoint.position.y);
    let f = footprint;
    // No box reaches further from the waypoint than this, so the square around it that this
    // spans (a centimetre wider, far beyond rounding) holds every point that can hit: the rest
    // of the room is passed over in single precision, without turning it into the robot's frame.
    let reach = f.reach() as f32;
    let (cx, cy) = (wx as f32, wy as f32);
    // Each core counts the hits of a block of the cloud; joined left to right, keeping the
    // earlier point on a tie, as one pass in the cloud's order would.
    let (hits, nearest) = cloud
        .par_chunks(CLEARANCE_BLOCK)
        .map(|points| {
            let mut hits = 0;
            let mut nearest: Option<(f64, Point3<f64>)> = None;
            for p in points {
                if (p.x - cx).abs() > reach || (p.y - cy).abs() > reach {
                    continue;
                }
                let p: Point3<f64> = p.cast();
                if p.z < f.floor_clearance || p.z > f.height {
                    continue;
                }
                // Into the robot's frame at the waypoint: x ahead, y to its left.
                let (dx, dy) = (p.x - wx, p.y - wy);
                let (x, y) = (cos * dx + sin * dy, -sin * dx + cos * dy);
                let in_base = x.abs() <= f.base_half_length && y.abs() <= f.base_half_width;
                let in_arm = x > f.base_half_length
                    && x <= f.arm_reach
                    && y.abs() <= f.arm_half_width
                    && (p.z - hand_height).abs() <= f.arm_half_height;
                if in_base || in_arm {
                    hits += 1;
                    let d = x * x + y * y;
                    if nearest.is_none_or(|(best, _)| d < best) {
                        nearest = Some((d, p));
                    }
                }
            }
            (hits, nearest)
        })
        .reduce(
            || (0, None),
            |(hits_left, left), (hits_right, right)| {
                let nearest = match (left, right) {
                    (Some(l), Some(r)) => Some(if r.0 < l.0 { r } else { l }),
                    (l, r) => l.or(r),
                };
                (hits_left + hits_right, nearest)
            },
        );
    match nearest {
        Some((_, p)) if hits > f.tolerated_points => {
            Clearance::Blocked { points: hits, nearest: p }
        }
        _ => Clearance::Clear,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waypoint_is_half_a_metre_out_facing_the_tag() {
        let plane = BackingPlane { normal: Vector3::new(-1.0, 0.0, 0.0), offset: 2.0, points: 500 };
        let tag = Point3::new(1.99, 0.3, 1.2);
        let w = approach_waypoint(&tag, &plane, 0.5).unwrap();
        assert!((w.position - Point3::new(1.49, 0.3, 1.2)).norm() < 1e-12);
        assert!(w.yaw.abs() < 1e-12, "facing +x, toward the wall");
        let floor = BackingPlane { normal: Vector3::z(), offset: 0.0, points: 500 };
        assert_eq!(approach_waypoint(&tag, &floor, 0.5), None);
    }

    #[test]
    fn a_chair_in_the_way_blocks_and_the_wall_ahead_does_not() {
        let w = ApproachWaypoint { position: Point3::new(1.5, 0.0, 1.0), yaw: 0.0 };
        let wall: Vec<Point3<f32>> =
            (0..100).map(|i| Point3::new(2.0, -0.5 + i as f32 * 0.01, 1.0)).collect();
        assert_eq!(check_clearance(&wall, &w, 1.0, &RobotFootprint::default()), Clearance::Clear);
        let mut cluttered = wall.clone();
        cluttered.extend((0..20).map(|i| Point3::new(1.6, 0.1, 0.3 + i as f32 * 0.01)));
        assert!(matches!(
            check_clearance(&cluttered, &w, 1.0, &RobotFootprint::default()),
            Clearance::Blocked { points: 20, .. }
        ));
        // The same box in the arm's path: only at the hand's height does it block.
        let in_arm: Vec<Point3<f32>> =
            (0..10).map(|i| Point3::new(1.85, 0.0, 0.98 + i as f32 * 0.004)).collect();
        assert!(matches!(
            check_clearance(&in_arm, &w, 1.0, &RobotFootprint::default()),
            Clearance::Blocked { .. }
        ));
        assert_eq!(check_clearance(&in_arm, &w, 0.5, &RobotFootprint::default()), Clearance::Clear);
    }
}
