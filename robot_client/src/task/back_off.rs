//! Backing off after the read, to look at the tag again from the range it was first seen from,
//! over no ground but the ground the base came over ([`Trail`]), and coming back the same way.
//!
//! A colour model holds at the range it was learned at: the camera's flash at arm's length makes
//! a red tag paler and pinker than any look it was learned from (in the simulator, a Dycem patch
//! 45 cm away shows saturation 0.56 and hue 347°, at 1.2 m 0.77 and 355°). So the robot draws
//! its arm in and goes back until its camera is as far from the tag as when it first found it:
//! straight back where that stays on its way in, otherwise back along its way in (its turns
//! undone in place, its drives reversed) to where it stood when it first saw the tag.

use nalgebra::{Isometry2, Point3};

use super::drive::{camera_origin, odom_from_base};
use super::report::PhaseReport;
use super::run::TaskRobot;
use super::trail::{Move, Trail, between};
use crate::hal::{CameraCalibration, HalError, MobileBase, PlanarPose};
use crate::navigation::RobotFootprint;

/// A range this near the one the tag was first seen from is the same, metres: the flash's light
/// on the tag changes by 2 % per centimetre at 1 m.
const SAME_RANGE: f64 = 0.01;

/// Which way the robot backed off.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Way {
    /// Straight back the whole way: it stays on the ground the base came over.
    Straight,
    /// Back along the way it came to where it first saw the tag: straight back would have left
    /// that ground after `straight` metres.
    Retraced { straight: f64 },
}

/// How the robot went to look: the motions it made from where the hand was brought.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct BackOff {
    way: Way,
    moves: Vec<Move>,
}

/// Backs the base off from `here` (odometry frame) to look at the tag at `tag` (odometry frame)
/// from `seen_from` metres, keeping to `trail`; says where it went in the phase's notes.
/// `None` when it did not move: it stands about as far as that already.
pub(super) fn back_off(
    robot: &impl TaskRobot,
    tag: &Point3<f64>,
    seen_from: f64,
    trail: &Trail,
    footprint: &RobotFootprint,
    phase: &mut PhaseReport,
) -> Result<Option<BackOff>, HalError> {
    let here = robot.pose_estimate()?;
    let calibration = robot.calibration();
    let Some(back_off) = plan(&calibration, &here, tag, seen_from, trail, footprint) else {
        return Ok(None);
    };
    robot.move_to_extension(0.0, f64::INFINITY)?;
    if let (Way::Retraced { .. }, Some(height)) = (back_off.way, trail.hand_height()) {
        // Turning near the device, fingers at its height would sweep through it (a lamp's
        // chain); at the height they had on the way in they sweep only what they swept then.
        robot.move_to_height(height, f64::INFINITY)?;
    }
    make(robot, back_off.moves.iter().copied())?;
    let from = range(&calibration, &(here * back_off.looked()), tag);
    phase.note(match back_off.way {
        Way::Straight => format!(
            "backed off {:.2} m straight, over ground it came by, to look from {from:.2} m, as \
             far as the tag was first seen from: its colour was learned at that range",
            back_off.looked().translation.vector.norm()
        ),
        Way::Retraced { straight } => format!(
            "backed off along its way in ({}) to where it first saw the tag, to look from \
             {from:.2} m: straight back would have left the ground it came over after \
             {straight:.2} m",
            describe(&back_off.moves)
        ),
    });
    Ok(Some(back_off))
}

impl BackOff {
    /// A point seen from where the robot looked (base frame then) in the base frame where the
    /// hand was brought, by the motions as commanded: the way back undoes them, so the base
    /// stands there again, while odometry has drifted on the way there and back.
    pub(super) fn seen_from_the_hand(&self, point: &Point3<f64>) -> Point3<f64> {
        odom_from_base(&self.looked()) * point
    }

    /// Where the robot looked from, in the base frame where the hand was brought.
    fn looked(&self) -> PlanarPose {
        self.moves.iter().fold(PlanarPose::identity(), |pose, made| {
            pose * match *made {
                Move::Drive(distance) => Isometry2::translation(distance, 0.0),
                Move::Turn(angle) => Isometry2::rotation(angle),
            }
        })
    }
}

/// Drives back to where the hand was brought before the back-off, the way it backed off.
pub(super) fn come_back(
    robot: &impl TaskRobot,
    back_off: &BackOff,
    phase: &mut PhaseReport,
) -> Result<(), HalError> {
    make(robot, back_off.moves.iter().rev().map(|made| made.undone()))?;
    phase.note("came back the way it backed off");
    Ok(())
}

/// How to back off from `here`, as [`back_off`] chooses.
fn plan(
    calibration: &CameraCalibration,
    here: &PlanarPose,
    tag: &Point3<f64>,
    seen_from: f64,
    trail: &Trail,
    footprint: &RobotFootprint,
) -> Option<BackOff> {
    let camera = odom_from_base(here).inverse() * tag - camera_origin(calibration);
    // The base moves the camera along the floor only: the height between them stays.
    let back = (seen_from.powi(2) - camera.z.powi(2)).max(0.0).sqrt() - camera.x.hypot(camera.y);
    if back <= SAME_RANGE {
        return None;
    }
    let straight_back = |d: f64| here * Isometry2::translation(-d, 0.0);
    let straight = between(here, &straight_back(back))
        .take_while(|pose| trail.covers(footprint, pose))
        .last()
        .map_or(0.0, |pose| (pose.translation.vector - here.translation.vector).norm());
    if straight >= back - 1e-9 {
        return Some(BackOff { way: Way::Straight, moves: vec![Move::Drive(-back)] });
    }
    // Where it stood when it first saw the tag it saw it from that range; looking as it did
    // then, facing the same way, only the colour and size it looks for differ from that look.
    let moves = trail.moves_since_sighting().iter().rev().map(|made| made.undone()).collect();
    Some(BackOff { way: Way::Retraced { straight }, moves })
}

/// Makes `moves` with the base. They are the drives and turns it came by, undone as they were
/// commanded rather than steered to the poses odometry recorded: a base's own error in a drive
/// or a turn (a wheel a little larger than its maker says) then undoes itself on the way back,
/// where steering by odometry would add it up, and the hand would come back beside the tag.
fn make(base: &impl MobileBase, moves: impl Iterator<Item = Move>) -> Result<(), HalError> {
    for made in moves {
        match made {
            Move::Drive(distance) => base.drive(distance)?,
            Move::Turn(angle) => base.turn(angle)?,
        }
    }
    Ok(())
}

/// How far the camera is from the tag at `tag` (odometry frame) with the base at `pose`, metres.
fn range(calibration: &CameraCalibration, pose: &PlanarPose, tag: &Point3<f64>) -> f64 {
    (odom_from_base(pose).inverse() * tag - camera_origin(calibration)).norm()
}

/// The motions in words: "turned 68° back, drove 0.95 m back".
fn describe(moves: &[Move]) -> String {
    // What a person would not call a move is left out.
    let said: Vec<String> = moves
        .iter()
        .filter_map(|made| match *made {
            Move::Drive(d) if d.abs() >= 0.01 => {
                Some(format!("drove {:.2} m {}", d.abs(), if d < 0.0 { "back" } else { "ahead" }))
            }
            Move::Turn(a) if a.to_degrees().abs() >= 1.0 => {
                Some(format!("turned {:.0}° back", a.to_degrees().abs()))
            }
            _ => None,
        })
        .collect();
    said.join(", ")
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector2;

    use super::*;
    use crate::sim::head_camera;

    /// A tag on a wall 2 m ahead of the origin, 1.2 m up; the base starts at `start`, facing
    /// it, and the trail then turns toward a waypoint half a metre out from the tag, drives
    /// there and turns to face the tag.
    fn approach(start: Vector2<f64>) -> (Point3<f64>, Trail, PlanarPose) {
        let tag = Point3::new(2.0, 0.0, 1.2);
        let facing = |at: Vector2<f64>| (tag.y - at.y).atan2(tag.x - at.x);
        let first = PlanarPose::new(start, facing(start));
        let mut trail = Trail::starting_at(first);
        let waypoint = Vector2::new(1.5, 0.0);
        let toward = waypoint - start;
        let heading = toward.y.atan2(toward.x);
        let turned = PlanarPose::new(start, heading);
        let arrived = PlanarPose::new(waypoint, heading);
        let faced = PlanarPose::new(waypoint, facing(waypoint));
        trail.push(Move::Turn(heading - facing(start)), turned);
        trail.push(Move::Drive(toward.norm()), arrived);
        trail.push(Move::Turn(facing(waypoint) - heading), faced);
        (tag, trail, faced)
    }

    fn seen_from(calibration: &CameraCalibration, trail: &Trail, tag: &Point3<f64>) -> f64 {
        range(calibration, &trail.since_sighting()[0], tag)
    }

    #[test]
    fn straight_back_where_the_base_came_straight() {
        let calibration = head_camera(0.25);
        let (tag, trail, here) = approach(Vector2::new(0.5, 0.0));
        let from = seen_from(&calibration, &trail, &tag);
        let footprint = RobotFootprint::default();
        let plan = plan(&calibration, &here, &tag, from, &trail, &footprint).unwrap();
        assert_eq!(plan.way, Way::Straight);
        assert_eq!(plan.moves.len(), 1);
        assert!((range(&calibration, &(here * plan.looked()), &tag) - from).abs() < 1e-6);
    }

    #[test]
    fn along_the_way_in_where_the_base_came_from_the_side() {
        let calibration = head_camera(0.25);
        let (tag, trail, here) = approach(Vector2::new(0.9, 0.7));
        let from = seen_from(&calibration, &trail, &tag);
        let footprint = RobotFootprint::default();
        let plan = plan(&calibration, &here, &tag, from, &trail, &footprint).unwrap();
        let Way::Retraced { straight } = plan.way else { panic!("{plan:?}") };
        assert!(straight < 0.1, "straight back stays on its way in for {straight:.2} m");
        // Made from here, the motions pass over the ground it came by to where it saw the tag.
        let mut at = here;
        for made in &plan.moves {
            let next = match *made {
                Move::Drive(d) => at * Isometry2::translation(d, 0.0),
                Move::Turn(a) => at * Isometry2::rotation(a),
            };
            assert!(between(&at, &next).all(|pose| trail.covers(&footprint, &pose)), "{made:?}");
            at = next;
        }
        let first = trail.since_sighting()[0];
        assert!((at.translation.vector - first.translation.vector).norm() < 1e-9);
        assert!((at.rotation.inverse() * first.rotation).angle().abs() < 1e-9);
        let looked = here * plan.looked();
        assert!((looked.translation.vector - first.translation.vector).norm() < 1e-9);
    }

    #[test]
    fn no_back_off_where_the_camera_is_as_far_already() {
        let calibration = head_camera(0.25);
        let (tag, trail, here) = approach(Vector2::new(0.5, 0.0));
        let near = range(&calibration, &here, &tag);
        let footprint = RobotFootprint::default();
        assert_eq!(plan(&calibration, &here, &tag, near + 0.005, &trail, &footprint), None);
    }
}
