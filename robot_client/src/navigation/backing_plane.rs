//! The backing plane: the surface the tag rests on, whose normal the robot approaches along.
//!
//! The paper's robot kept "the remaining plane whose member points come closest to the
//! user-selected 3D location" ([`nearest_plane_to_target`], kept for comparison). From oblique
//! starts that picked a drawer's side face, its only failures in Table I. The side face does
//! face the robot and does come close to the target, but the tag is not in front of it: the tag
//! lies behind the side face's plane. So [`choose_backing_plane`] asks of each plane what a
//! surface carrying the tag must satisfy, and then takes the nearest one behind the tag:
//! roughly vertical; broad through most of its points (a wall or a cabinet front, not a sliver
//! of a lamp shade, nor a lamp's pole with its shade's rim beside it); facing the robot, not seen
//! edge-on; with the tag's centroid on or in front of it; and with its own points beside the
//! tag's foot on it.
//!
//! A tag can also hang free before a surface: a foam tube on a lamp's pull chain, a hand span in
//! front of the wall. Then whatever lines up with the tag nearer the robot (the lamp's pole, the
//! chain and the rim of its shade) may pass for a plane through the tag, nearer than the wall. A
//! surface carrying the tag would hide what lies behind the tag's shadow; when a plane behind
//! the tag shows its own points on every side of that shadow, nothing solid stands between, so
//! no plane nearer the tag can carry it, not even one the tag also hangs free before (a pole
//! with the shade's rim and chain scattered about the tube shows "around" its shadow too).

use nalgebra::{Point3, Vector3};

use super::plane::Plane;
use super::ransac::DetectedPlane;
use super::rejection::{PlaneRejection, RejectedPlane};
use super::robust_width::width_through_most;

/// The plane the robot will approach perpendicular to.
#[derive(Debug, Clone, PartialEq)]
pub struct BackingPlane {
    /// Unit normal pointing toward the robot.
    pub normal: Vector3<f64>,
    /// `normal · p + offset = 0` on the plane, metres.
    pub offset: f64,
    /// How many laser points lie on it.
    pub points: usize,
}

impl BackingPlane {
    fn from_detected(plane: &DetectedPlane) -> Self {
        Self { normal: plane.plane.normal, offset: plane.plane.offset, points: plane.inliers.len() }
    }
}

/// What a surface carrying the tag must satisfy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BackingPlaneRule {
    /// Largest angle of the normal from horizontal, radians (walls and fronts are vertical).
    pub max_tilt: f64,
    /// Largest angle between the normal and the direction from the tag to the robot, radians.
    pub max_facing_angle: f64,
    /// How far behind the plane the tag's centroid may sit (its estimate's noise), metres.
    pub tag_behind_tolerance: f64,
    /// How far in front of the plane the tag may hang (a pull chain before a wall), metres.
    pub max_tag_height: f64,
    /// Greatest gap between the tag's foot on the plane and the plane's nearest point beyond the
    /// tag's own reach, metres: the surface must show itself beside the tag.
    pub max_foot_gap: f64,
    /// Least width of the plane in both in-plane directions, metres, through most of its
    /// points: a pole with a scatter beside it is as narrow as the pole.
    pub min_extent: f64,
    /// How far beyond the tag's own shadow on a plane behind it, metres, the plane must show
    /// its points on every side for the tag to hang free before it: wider than the laser's
    /// parallax from the camera over a tag's standoff.
    pub free_ring: f64,
    /// Least points of the plane on each side of the shadow (left, right, above, below).
    pub free_min_points: usize,
}

impl Default for BackingPlaneRule {
    fn default() -> Self {
        Self {
            max_tilt: 20f64.to_radians(),
            max_facing_angle: 80f64.to_radians(),
            tag_behind_tolerance: 0.02,
            max_tag_height: 0.5,
            max_foot_gap: 0.15,
            min_extent: 0.15,
            free_ring: 0.12,
            free_min_points: 5,
        }
    }
}

impl BackingPlaneRule {
    /// This rule for depths scattering with standard deviation `sigma` (metres) about the
    /// target: the tag's centroid may sit as far behind its surface as the noise moves it.
    pub fn for_depth_noise(&self, sigma: f64) -> Self {
        Self { tag_behind_tolerance: self.tag_behind_tolerance.max(sigma), ..*self }
    }
}

/// The backing plane, if any qualified, and why every other plane did not.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BackingChoice {
    pub plane: Option<BackingPlane>,
    /// Its index among the planes judged.
    pub index: Option<usize>,
    pub rejected: Vec<RejectedPlane>,
}

/// The plane behind the tag, nearest to it, among those that could carry it and have no plane
/// behind them that shows all around the tag's shadow. `points` is the cloud the planes' inlier
/// indices refer to; `tag_points` are the tag's own points (a flat tag lies flat on its surface:
/// of two surfaces behind it, the one it sits nearer and flatter against carries it, not a side
/// face that happens to pass through it); `tag_radius` is how far the tag's own points reach
/// from its centroid (metres): a big towel covers the front right around its foot.
pub fn choose_backing_plane(
    planes: &[DetectedPlane],
    points: &[Point3<f32>],
    tag: &Point3<f64>,
    tag_radius: f64,
    tag_points: &[Point3<f32>],
    robot: &Point3<f64>,
    rule: &BackingPlaneRule,
) -> BackingChoice {
    let d = robot - tag;
    let toward_robot = Vector3::new(d.x, d.y, 0.0).try_normalize(1e-9).unwrap_or(Vector3::x());
    // For each plane that could carry the tag, how far the tag sits from it: its height plus
    // how thick it is across the plane.
    let verdicts: Vec<Result<f64, PlaneRejection>> = planes
        .iter()
        .map(|p| {
            let height = judge(p, points, tag, tag_radius, tag_points, &toward_robot, rule)?;
            Ok(height.max(0.0) + spread_across(tag_points, &p.plane))
        })
        .collect();
    // How far the tag hangs before each plane that could carry it and that it hangs free before.
    let free_before: Vec<Option<f64>> = planes
        .iter()
        .zip(&verdicts)
        .map(|(p, verdict)| {
            verdict.as_ref().ok()?;
            hangs_free_before(p, points, tag, tag_radius, robot, rule)
        })
        .collect();
    // For each plane, how far the tag hangs free before a plane behind it: then this one only
    // lines up with the tag, and that holds for a plane the tag hangs free before too. A
    // surface would hide what lies behind the tag's shadow; seen through there, it is none
    // (a lamp's pole with its shade's rim and chain scattered about the tube).
    let lines_up: Vec<Option<f64>> = planes
        .iter()
        .map(|nearer| {
            let height = nearer.plane.signed_distance(tag);
            free_before
                .iter()
                .flatten()
                .copied()
                .filter(|&behind| behind > height + rule.tag_behind_tolerance)
                .min_by(f64::total_cmp)
        })
        .collect();
    let may_carry = |i: usize| lines_up[i].is_none();
    let chosen = verdicts
        .iter()
        .enumerate()
        .filter(|&(i, _)| may_carry(i))
        .filter_map(|(i, v)| v.as_ref().ok().map(|&fit| (i, fit)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let rejected = planes
        .iter()
        .zip(&verdicts)
        .enumerate()
        .filter(|&(i, _)| chosen.is_none_or(|(c, _)| c != i))
        .map(|(i, (p, verdict))| RejectedPlane {
            normal: p.plane.normal,
            offset: p.plane.offset,
            points: p.inliers.len(),
            why: match *verdict {
                Err(why) => why,
                Ok(_) if !may_carry(i) => {
                    PlaneRejection::TagHangsFree { before: lines_up[i].unwrap_or(0.0) }
                }
                Ok(fit) => PlaneRejection::FartherThanChosen {
                    fit,
                    chosen: chosen.map_or(0.0, |(_, h)| h),
                },
            },
        })
        .collect();
    BackingChoice {
        plane: chosen.map(|(i, _)| BackingPlane::from_detected(&planes[i])),
        index: chosen.map(|(i, _)| i),
        rejected,
    }
}

/// How far the tag hangs before `p` (metres) when it hangs free before it: the robot sees the
/// tag's shadow on `p` (where the line from the robot through the tag meets it) with `p`'s own
/// points on every side, in a ring beyond the shadow of the tag's own reach. `None` when the
/// tag rests on `p` or `p` is hidden around the shadow.
fn hangs_free_before(
    p: &DetectedPlane,
    points: &[Point3<f32>],
    tag: &Point3<f64>,
    tag_radius: f64,
    robot: &Point3<f64>,
    rule: &BackingPlaneRule,
) -> Option<f64> {
    let plane = &p.plane;
    let sight = tag - robot;
    let toward = plane.normal.dot(&sight);
    if toward.abs() < 1e-9 {
        return None;
    }
    // The line of sight meets the plane at robot + scale · sight; beyond the tag, the tag's
    // shadow is `scale` times the tag's size.
    let scale = -plane.signed_distance(robot) / toward;
    let height = plane.signed_distance(tag);
    if scale <= 1.0 || height <= rule.tag_behind_tolerance {
        return None;
    }
    let shadow = robot + sight * scale;
    let inner = tag_radius * scale;
    let outer = inner + rule.free_ring;
    let (across, up) = plane.basis();
    // Points on the right, above, on the left and below the shadow.
    let mut sides = [0usize; 4];
    for &i in &p.inliers {
        let d = points[i as usize].cast::<f64>() - shadow;
        let (a, b) = (across.dot(&d), up.dot(&d));
        // Squared, against squared radii: `hypot` per point was most of this rule's time.
        let r_squared = a * a + b * b;
        if r_squared < inner * inner || r_squared > outer * outer {
            continue;
        }
        let side = match (a.abs() >= b.abs(), a > 0.0, b > 0.0) {
            (true, true, _) => 0,
            (false, _, true) => 1,
            (true, false, _) => 2,
            (false, _, false) => 3,
        };
        sides[side] += 1;
    }
    sides.iter().all(|&n| n >= rule.free_min_points).then_some(height)
}

/// Mean absolute deviation of the points' distances from `plane` about their median, metres:
/// about the laser's noise for a tag lying flat on it, its width for a plane it stands across.
fn spread_across(points: &[Point3<f32>], plane: &Plane) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let mut d: Vec<f64> = points.iter().map(|p| plane.signed_distance(&p.cast())).collect();
    let half = d.len() / 2;
    let median = *d.select_nth_unstable_by(half, f64::total_cmp).1;
    d.iter().map(|x| (x - median).abs()).sum::<f64>() / d.len() as f64
}

/// Whether the tag's points lie along `plane` rather than across it: their spread across it
/// is within what the depth noise moves a tag's centroid, where a tag standing across a plane
/// spreads a quarter of its width.
fn lies_flat_on(tag_points: &[Point3<f32>], plane: &Plane, rule: &BackingPlaneRule) -> bool {
    !tag_points.is_empty() && spread_across(tag_points, plane) <= rule.tag_behind_tolerance
}

/// The width through most of the plane's points and the tag's together.
fn width_with_tag(p: &DetectedPlane, points: &[Point3<f32>], tag_points: &[Point3<f32>]) -> f64 {
    let together: Vec<Point3<f32>> =
        p.inliers.iter().map(|&i| points[i as usize]).chain(tag_points.iter().copied()).collect();
    let all: Vec<u32> = (0..together.len() as u32).collect();
    width_through_most(&together, &all, &p.plane).unwrap_or(0.0)
}

/// How far in front of `p` the tag is when `p` could carry it; otherwise the rule it fails.
fn judge(
    p: &DetectedPlane,
    points: &[Point3<f32>],
    tag: &Point3<f64>,
    tag_radius: f64,
    tag_points: &[Point3<f32>],
    toward_robot: &Vector3<f64>,
    rule: &BackingPlaneRule,
) -> Result<f64, PlaneRejection> {
    let plane = &p.plane;
    let tilt = plane.tilt_from_vertical();
    if tilt > rule.max_tilt {
        return Err(PlaneRejection::Tilted { tilt, max: rule.max_tilt });
    }
    // Broad through most of its points, not only through a few stray ones far out.
    let mut width =
        width_through_most(points, &p.inliers, plane).map_or(p.extent[1], |w| w.min(p.extent[1]));
    // A tag lying flat on a surface hides the part of it that it covers (a towel over most of
    // a narrow front, a bin hiding the rest): such a surface is as wide as its own points and
    // the tag's together.
    if width < rule.min_extent && lies_flat_on(tag_points, plane, rule) {
        width = width.max(width_with_tag(p, points, tag_points));
    }
    if width < rule.min_extent {
        return Err(PlaneRejection::Small { width, min: rule.min_extent });
    }
    // Judged in the horizontal: a camera pitched down sees a wall's normal tipped up at it.
    let horizontal = Vector3::new(plane.normal.x, plane.normal.y, 0.0)
        .try_normalize(1e-9)
        .unwrap_or(plane.normal);
    let facing = horizontal.dot(toward_robot).clamp(-1.0, 1.0).acos();
    if facing > rule.max_facing_angle {
        return Err(PlaneRejection::EdgeOn { angle: facing, max: rule.max_facing_angle });
    }
    let height = plane.signed_distance(tag);
    if height < -rule.tag_behind_tolerance {
        return Err(PlaneRejection::TagBehind {
            depth: -height,
            tolerance: rule.tag_behind_tolerance,
        });
    }
    if height > rule.max_tag_height {
        return Err(PlaneRejection::TagTooFarOut { height, max: rule.max_tag_height });
    }
    let foot = tag - plane.normal * height;
    let gap = p
        .inliers
        .iter()
        .map(|&i| (points[i as usize].cast::<f64>() - foot).norm_squared())
        .fold(f64::INFINITY, f64::min)
        .sqrt();
    let max_gap = rule.max_foot_gap + tag_radius;
    if gap > max_gap {
        return Err(PlaneRejection::AwayFromTag { gap, max: max_gap });
    }
    Ok(height)
}

/// The paper's rule: the plane whose points come closest to the target, whatever it is.
pub fn nearest_plane_to_target(
    planes: &[DetectedPlane],
    points: &[Point3<f32>],
    target: &Point3<f64>,
) -> Option<BackingPlane> {
    planes
        .iter()
        .map(|p| {
            let nearest = p
                .inliers
                .iter()
                .map(|&i| (points[i as usize].cast::<f64>() - target).norm_squared())
                .fold(f64::INFINITY, f64::min);
            (p, nearest)
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(p, _)| BackingPlane::from_detected(p))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::navigation::plane::Plane;

    /// A plane patch of points on a grid, as the plane search would report it.
    fn patch(
        points: &mut Vec<Point3<f32>>,
        corner: Point3<f64>,
        a: Vector3<f64>,
        b: Vector3<f64>,
        toward: &Point3<f64>,
    ) -> DetectedPlane {
        grid_patch(points, corner, a, b, 20, toward, |_| true)
    }

    /// A patch on a grid of `steps` × `steps` cells, of the points `seen` keeps.
    fn grid_patch(
        points: &mut Vec<Point3<f32>>,
        corner: Point3<f64>,
        a: Vector3<f64>,
        b: Vector3<f64>,
        steps: u32,
        toward: &Point3<f64>,
        seen: impl Fn(&Point3<f64>) -> bool,
    ) -> DetectedPlane {
        let start = points.len() as u32;
        for i in 0..=steps {
            for j in 0..=steps {
                let (u, v) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                let p = corner + a * u + b * v;
                if seen(&p) {
                    points.push(p.cast());
                }
            }
        }
        DetectedPlane { extent: [a.norm(), b.norm()], ..fitted(points, start, toward) }
    }

    /// The points from `start` on, fitted and reported as the plane search would.
    fn fitted(points: &[Point3<f32>], start: u32, toward: &Point3<f64>) -> DetectedPlane {
        let inliers: Vec<u32> = (start..points.len() as u32).collect();
        let (plane, centroid) =
            Plane::fit(inliers.iter().map(|&i| points[i as usize].cast())).unwrap();
        DetectedPlane {
            plane: plane.facing(toward),
            centroid,
            inliers,
            extent: [0.0; 2],
            noise: 0.0,
            inlier_distance: 0.012,
        }
    }

    /// The robot, and 1.2 m ahead of it a tag 30 cm before the wall x = 2 (facing -x).
    fn robot_and_tag() -> (Point3<f64>, Point3<f64>) {
        (Point3::new(0.5, 0.0, 1.0), Point3::new(1.7, 0.0, 1.0))
    }

    /// The wall x = 2, 60 cm wide around y = 0, from `bottom` up `height` metres.
    fn wall(
        points: &mut Vec<Point3<f32>>,
        bottom: f64,
        height: f64,
        toward: &Point3<f64>,
    ) -> DetectedPlane {
        patch(
            points,
            Point3::new(2.0, -0.3, bottom),
            Vector3::new(0.0, 0.6, 0.0),
            Vector3::new(0.0, 0.0, height),
            toward,
        )
    }

    /// The choice among `planes` for a small tag (3 cm across, its own points not given) with
    /// the default rule, asserting that the second plane carries it.
    fn second_carries(
        planes: &[DetectedPlane],
        points: &[Point3<f32>],
        tag: &Point3<f64>,
        robot: &Point3<f64>,
    ) -> BackingChoice {
        let rule = BackingPlaneRule::default();
        let choice = choose_backing_plane(planes, points, tag, 0.03, &[], robot, &rule);
        assert_eq!(choice.index, Some(1), "{:?}", choice.rejected);
        choice
    }

    /// Why the one plane the choice turned down was turned down; fails when it turned down
    /// none or several.
    fn the_one_rejection(choice: &BackingChoice) -> PlaneRejection {
        match &choice.rejected[..] {
            [only] => only.why,
            other => panic!("expected one rejected plane, got {other:?}"),
        }
    }

    #[test]
    fn the_side_face_near_the_target_is_not_the_backing_plane() {
        // A cabinet whose front is the plane x = 2 (facing -x) and whose left side is y = 0.2;
        // the robot stands off to the front-left, the target estimate overshot to just beside the corner.
        let robot = Point3::new(1.0, 1.2, 0.7);
        let mut points = Vec::new();
        let front = patch(
            &mut points,
            Point3::new(2.0, -0.2, 0.3),
            Vector3::new(0.0, 0.4, 0.0),
            Vector3::new(0.0, 0.0, 0.6),
            &robot,
        );
        let side = patch(
            &mut points,
            Point3::new(2.0, 0.2, 0.3),
            Vector3::new(0.5, 0.0, 0.0),
            Vector3::new(0.0, 0.0, 0.6),
            &robot,
        );
        let planes = vec![front.clone(), side.clone()];
        let tag = Point3::new(1.99, 0.1, 0.6);
        let target = Point3::new(2.03, 0.23, 0.6);
        let paper = nearest_plane_to_target(&planes, &points, &target).unwrap();
        assert!(paper.normal.y > 0.99, "the paper's rule takes the side face");
        let choice = choose_backing_plane(
            &planes,
            &points,
            &tag,
            0.1,
            &[],
            &robot,
            &BackingPlaneRule::default(),
        );
        let ours = choice.plane.as_ref().unwrap();
        assert!(
            matches!(the_one_rejection(&choice), PlaneRejection::TagBehind { .. }),
            "{:?}",
            choice.rejected
        );
        assert!(ours.normal.x < -0.99, "the front carries the tag");
        assert!((ours.offset - 2.0).abs() < 1e-6);
    }

    #[test]
    fn a_tag_hanging_before_the_wall_is_carried_by_the_wall_not_by_what_lines_up_with_it() {
        // A foam tube 30 cm before the wall x = 2, and a lamp's pole, chain and shade lining up
        // into a plane through the tube, turned 60° from the wall.
        let (robot, tag) = robot_and_tag();
        let mut points = Vec::new();
        let wall = wall(&mut points, 0.7, 0.6, &robot);
        let along = Vector3::new(60f64.to_radians().sin(), 60f64.to_radians().cos(), 0.0);
        let lined_up = patch(
            &mut points,
            tag - along * 0.05 - Vector3::new(0.0, 0.0, 0.4),
            along * 0.25,
            Vector3::new(0.0, 0.0, 0.8),
            &robot,
        );
        let planes = vec![lined_up, wall];
        let paper = nearest_plane_to_target(&planes, &points, &tag).unwrap();
        assert!(paper.normal.x > -0.9, "the paper's rule takes the plane through the tag");
        let choice = second_carries(&planes, &points, &tag, &robot);
        assert!(choice.plane.as_ref().unwrap().normal.x < -0.99);
        match the_one_rejection(&choice) {
            PlaneRejection::TagHangsFree { before } => {
                assert!((before - 0.3).abs() < 1e-6, "{before}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_pole_with_a_scatter_beside_it_is_too_narrow_to_carry_the_tag() {
        // A foam tube 30 cm before the wall x = 2, a lamp's shade hiding the wall above it (so
        // the tag cannot be seen to hang free), and a plane through the tube holding the lamp's
        // pole (3 cm across) and a fifth as many points of the shade's rim scattered 40 cm wide:
        // 24 cm "wide" by its variance, as broad as a narrow front.
        let (robot, tag) = robot_and_tag();
        let mut points = Vec::new();
        let wall = wall(&mut points, 0.5, 0.45, &robot);
        let along = Vector3::new(60f64.to_radians().sin(), 60f64.to_radians().cos(), 0.0);
        let start = points.len() as u32;
        let foot = tag + along * 0.02 - Vector3::new(0.0, 0.0, 0.4);
        for i in 0..800 {
            let (across, up) = (0.03 * f64::from(i % 8) / 8.0, 0.8 * f64::from(i / 8) / 100.0);
            points.push((foot + along * across + Vector3::z() * up).cast());
        }
        for i in 0..200 {
            let side = if i % 2 == 0 { -1.0 } else { 1.0 };
            let across = side * (0.05 + 0.15 * f64::from(i % 10) / 10.0);
            points.push(
                (foot + along * across + Vector3::z() * (0.7 + 0.0005 * f64::from(i))).cast(),
            );
        }
        let pole = DetectedPlane {
            extent: [0.8, 0.24],
            noise: 0.012,
            inlier_distance: 0.03,
            ..fitted(&points, start, &robot)
        };
        let planes = vec![pole, wall];
        let choice = second_carries(&planes, &points, &tag, &robot);
        match the_one_rejection(&choice) {
            PlaneRejection::Small { width, .. } => {
                assert!(width < 0.06, "{width}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_plane_the_tag_hangs_before_but_the_wall_shows_through_does_not_carry_it() {
        // A foam tube 30 cm before the wall x = 2, seen all around its shadow; 5 cm behind the
        // tube, things lined up into a plane that itself shows around the tube's shadow on it,
        // though the wall shows through it there: no surface.
        let (robot, tag) = robot_and_tag();
        let mut points = Vec::new();
        let wall = wall(&mut points, 0.7, 0.6, &robot);
        let along = Vector3::new(60f64.to_radians().sin(), 60f64.to_radians().cos(), 0.0);
        let lined_up = patch(
            &mut points,
            tag + Vector3::new(0.05, 0.0, 0.0) - along * 0.3 - Vector3::new(0.0, 0.0, 0.4),
            along * 0.6,
            Vector3::new(0.0, 0.0, 0.8),
            &robot,
        );
        let planes = vec![lined_up, wall];
        let choice = second_carries(&planes, &points, &tag, &robot);
        assert!(
            matches!(the_one_rejection(&choice), PlaneRejection::TagHangsFree { .. }),
            "{:?}",
            choice.rejected
        );
    }

    #[test]
    fn a_narrow_front_hiding_the_wall_below_the_tag_carries_it() {
        // A towel at the top of a front 20 cm wide (x = 1.71); the wall x = 2 behind shows to
        // the left and right of the front and above it, but the front hides it below the
        // towel's shadow: the towel rests on the front.
        let (robot, tag) = robot_and_tag();
        let mut points = Vec::new();
        let front = patch(
            &mut points,
            Point3::new(1.71, -0.1, 0.5),
            Vector3::new(0.0, 0.2, 0.0),
            Vector3::new(0.0, 0.0, 0.55),
            &robot,
        );
        // The front's silhouette on the wall, seen from the robot: 1.5 / 1.21 times as large.
        let enlarged = 1.5 / 1.21;
        let wall = grid_patch(
            &mut points,
            Point3::new(2.0, -0.3, 0.7),
            Vector3::new(0.0, 0.6, 0.0),
            Vector3::new(0.0, 0.0, 0.6),
            60,
            &robot,
            |p| p.y.abs() > 0.1 * enlarged || p.z > 1.0 + 0.05 * enlarged,
        );
        let planes = vec![wall, front];
        second_carries(&planes, &points, &tag, &robot);
    }

    #[test]
    fn a_wall_seen_only_above_a_cabinet_leaves_the_tag_on_its_front() {
        // A tag near the top of a cabinet front x = 1.7; the wall x = 2.1 behind the cabinet
        // shows only above it, so around the tag's shadow on it the cabinet hides one side.
        let robot = Point3::new(0.5, 0.0, 1.0);
        let tag = Point3::new(1.69, 0.0, 0.88);
        let mut points = Vec::new();
        let front = patch(
            &mut points,
            Point3::new(1.7, -0.25, 0.4),
            Vector3::new(0.0, 0.5, 0.0),
            Vector3::new(0.0, 0.0, 0.5),
            &robot,
        );
        let wall = patch(
            &mut points,
            Point3::new(2.1, -0.5, 0.92),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 0.5),
            &robot,
        );
        let planes = vec![wall, front];
        let choice = second_carries(&planes, &points, &tag, &robot);
        assert!(
            matches!(the_one_rejection(&choice), PlaneRejection::FartherThanChosen { .. }),
            "{:?}",
            choice.rejected
        );
    }

    #[test]
    fn a_towel_flat_on_a_front_it_mostly_hides_widens_the_front() {
        // Of a front x = 1.71 only a strip 8 cm wide shows beside a towel 14 × 16 cm lying on
        // it 1 cm proud: the strip alone is narrower than a surface, the two together are not.
        let robot = Point3::new(0.5, 0.0, 1.0);
        let mut points = Vec::new();
        let front = patch(
            &mut points,
            Point3::new(1.71, 0.10, 0.8),
            Vector3::new(0.0, 0.08, 0.0),
            Vector3::new(0.0, 0.0, 0.4),
            &robot,
        );
        let towel: Vec<Point3<f32>> = (0..35)
            .flat_map(|i| (0..8).map(move |j| (i, j)))
            .map(|(i, j)| Point3::new(1.70, -0.04 + 0.004 * i as f32, 0.92 + 0.02 * j as f32))
            .collect();
        let tag = Point3::new(1.70, 0.03, 1.0);
        let rule = BackingPlaneRule::default();
        let planes = [front];
        let lying = choose_backing_plane(&planes, &points, &tag, 0.11, &towel, &robot, &rule);
        assert_eq!(lying.index, Some(0), "{:?}", lying.rejected);
        // The same towel standing across the front, 12 cm deep toward the robot, is no part of
        // the front's width.
        let across: Vec<Point3<f32>> =
            towel.iter().map(|p| Point3::new(1.70 - 3.0 * (p.y + 0.04), 0.03, p.z)).collect();
        let tag = Point3::new(1.64, 0.03, 1.0);
        let standing = choose_backing_plane(&planes, &points, &tag, 0.11, &across, &robot, &rule);
        assert!(
            matches!(the_one_rejection(&standing), PlaneRejection::Small { .. }),
            "{:?}",
            standing.rejected
        );
    }
}
