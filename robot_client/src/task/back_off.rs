//! Backing off after the read, to look at the tag again from the range it was first seen from,
//! with the whole robot ([`Outline`]: the base, and the arm and hand drawn in ahead of it) over
//! no ground and through no air but what it came through ([`Trail`]), and coming back the same
//! way.
//!
//! A colour model holds at the range it was learned at: the camera's flash at arm's length makes
//! a red tag paler and pinker than any look it was learned from (in the simulator, a Dycem patch
//! 45 cm away shows saturation 0.56 and hue 347°, at 1.2 m 0.77 and 355°). So the robot draws
//! its arm in and goes back until its camera is as far from the tag as when it first found it:
//! straight back where that stays inside what it swept on its way in, otherwise back along its
//! way in to where it stood when it first saw the tag: every motion since undone in the reverse
//! order, the carriage's too, so that the hand is lowered or raised where it was raised or
//! lowered then and turns at the height it turned at then. That way it sweeps what it swept
//! then by construction, the arm drawn in inside the air the arm swept reaching out; only the
//! straight way is checked, and where the whole robot would leave what it swept, it retraces.
//!
//! The base stops on its own when something is in its way (a person stepping behind it), and
//! says so only by having gone less far. A back-off stopped partway is not finished as planned
//! from where it stopped: the robot comes back by the motions it made, as odometry tells them
//! ([`as_made`]), and acts where it first saw the tag.

use nalgebra::Point3;

use super::as_made::as_made;
use super::drive::{camera_origin, odom_from_base};
use super::outline::{Outline, Stance, Swept};
use super::report::PhaseReport;
use super::task_robot::TaskRobot;
use super::trail::{Move, Trail, between};
use crate::hal::{CameraCalibration, HalError, PlanarPose};

/// A range this near the one the tag was first seen from is the same, metres: the flash's light
/// on the tag changes by 2 % per centimetre at 1 m.
const SAME_RANGE: f64 = 0.01;

/// Which way the robot backed off.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Way {
    /// Straight back the whole way: it stays inside what the robot swept on its way in.
    Straight,
    /// Back along the way it came to where it first saw the tag: straight back would have left
    /// what it swept after `straight` metres.
    Retraced { straight: f64 },
}

/// How the robot went to look: the motions it made from where the hand was brought.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct BackOff {
    way: Way,
    moves: Vec<Move>,
}

/// What came of backing off; the phase's notes say why.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Backing {
    /// It did not move: it stands about as far from the tag as it first saw it from.
    Stayed,
    /// It went to look; [`come_back`] brings it back.
    Went(BackOff),
    /// It does not look again: its base stopped on the way and it came back by the motions it
    /// had made.
    NoLook,
    /// Its base stopped on the way and again coming back: it is not where the hand was brought.
    Stranded,
}

/// Backs the robot off from where it stands to look at the tag at `tag` (odometry frame) from
/// `seen_from` metres, keeping inside `trail`; says where it went in the phase's notes.
pub(super) fn back_off(
    robot: &impl TaskRobot,
    tag: &Point3<f64>,
    seen_from: f64,
    trail: &Trail,
    outline: &Outline,
    phase: &mut PhaseReport,
) -> Result<Backing, HalError> {
    let drawn_in = Stance { base: robot.pose_estimate()?, height: robot.height()?, extension: 0.0 };
    let calibration = robot.calibration();
    let Some(back_off) = plan(&calibration, &drawn_in, tag, seen_from, trail, outline) else {
        return Ok(Backing::Stayed);
    };
    robot.move_to_extension(0.0, f64::INFINITY)?;
    let made = make(robot, back_off.moves.iter().copied())?;
    if let Some(stop) = made.stop {
        phase.note(format!(
            "backing off to look again, {}; came back by what it had made ({}), to act where it \
             first saw the tag without looking again",
            stop.describe(),
            describe(&undo(&made.moves))
        ));
        let back = make(robot, undo(&made.moves).into_iter())?;
        if let Some(stop) = back.stop {
            phase.fail(format!(
                "coming back, {}: the robot is not where the hand was brought and does not act",
                stop.describe()
            ));
            return Ok(Backing::Stranded);
        }
        return Ok(Backing::NoLook);
    }
    let back_off = BackOff { moves: made.moves, ..back_off };
    let from = range(&calibration, &(drawn_in.base * back_off.looked()), tag);
    phase.note(match back_off.way {
        Way::Straight => format!(
            "backed off {:.2} m straight, over ground it came by, to look from {from:.2} m, as \
             far as the tag was first seen from: its colour was learned at that range",
            back_off.looked().translation.vector.norm()
        ),
        Way::Retraced { straight } => format!(
            "backed off along its way in ({}) to where it first saw the tag, to look from \
             {from:.2} m: straight back the robot would have left the ground and air it came \
             through after {straight:.2} m",
            describe(&back_off.moves)
        ),
    });
    Ok(Backing::Went(back_off))
}

impl BackOff {
    /// A point seen from where the robot looked (base frame then) in the base frame where the
    /// hand was brought, by the motions as made: the way back undoes them, so the base stands
    /// there again, while odometry has drifted on the way there and back.
    pub(super) fn seen_from_the_hand(&self, point: &Point3<f64>) -> Point3<f64> {
        odom_from_base(&self.looked()) * point
    }

    /// Where the robot looked from, in the base frame where the hand was brought.
    fn looked(&self) -> PlanarPose {
        let start = Stance { base: PlanarPose::identity(), height: 0.0, extension: 0.0 };
        self.moves.iter().fold(start, |stance, made| made.after(&stance)).base
    }
}

/// Drives back to where the hand was brought before the back-off, the way it backed off;
/// `false`, failing the phase, when the base stopped on the way.
pub(super) fn come_back(
    robot: &impl TaskRobot,
    back_off: &BackOff,
    phase: &mut PhaseReport,
) -> Result<bool, HalError> {
    let back = make(robot, undo(&back_off.moves).into_iter())?;
    if let Some(stop) = back.stop {
        phase.fail(format!(
            "coming back from the look, {}: the robot is not where the hand was brought and \
             does not act",
            stop.describe()
        ));
        return Ok(false);
    }
    phase.note("came back the way it backed off");
    Ok(true)
}

/// How to back off from `drawn_in` (the arm drawn in where the hand was brought), as
/// [`back_off`] chooses; `None` where the camera is about as far from the tag already.
fn plan(
    calibration: &CameraCalibration,
    drawn_in: &Stance,
    tag: &Point3<f64>,
    seen_from: f64,
    trail: &Trail,
    outline: &Outline,
) -> Option<BackOff> {
    let camera = odom_from_base(&drawn_in.base).inverse() * tag - camera_origin(calibration);
    // The base moves the camera along the floor only: the height between them stays.
    let back = (seen_from.powi(2) - camera.z.powi(2)).max(0.0).sqrt() - camera.x.hypot(camera.y);
    if back <= SAME_RANGE {
        return None;
    }
    let swept = trail.swept();
    let straight_back = [Move::Drive(-back)];
    let straight = inside(outline, &swept, drawn_in, &straight_back);
    if straight >= back - 1e-9 {
        return Some(BackOff { way: Way::Straight, moves: straight_back.to_vec() });
    }
    // Where it stood when it first saw the tag it saw it from that range; looking as it did
    // then, facing the same way, only the colour and size it looks for differ from that look.
    // Every motion since undone in the reverse order, the robot sweeps what it swept then; the
    // arm stays drawn in, inside the air it swept reaching out.
    let moves = undo(trail.moves_since_sighting())
        .into_iter()
        .filter(|made| !matches!(made, Move::Reach { .. }))
        .collect();
    Some(BackOff { way: Way::Retraced { straight }, moves })
}

/// How far the base's centre travels making `moves` from `start` before the robot first leaves
/// `swept`, metres: all of their travel where it never does.
fn inside(outline: &Outline, swept: &[Swept], start: &Stance, moves: &[Move]) -> f64 {
    let mut at = *start;
    let mut covered = 0.0;
    for made in moves {
        let next = made.after(&at);
        let before = covered;
        for step in between(&at, &next) {
            if !outline.covered(swept, &step) {
                return covered;
            }
            covered = before + (step.base.translation.vector - at.base.translation.vector).norm();
        }
        at = next;
    }
    covered
}

/// The motions that undo `moves`, in the order that undoes them.
fn undo(moves: &[Move]) -> Vec<Move> {
    moves.iter().rev().map(|made| made.undone()).collect()
}

/// Motions as the robot made them, and where it stopped, if it did.
struct Made {
    /// The motions made, the last perhaps only partway.
    moves: Vec<Move>,
    stop: Option<Stop>,
}

/// A motion the robot stopped partway through.
struct Stop {
    commanded: Move,
    made: Move,
    /// What the robot's hardware said, when it said anything.
    error: Option<HalError>,
}

impl Stop {
    /// In words: "the base stopped after 0.31 m of a 0.94 m drive back (its safety stopped it:
    /// something was in its way)".
    fn describe(&self) -> String {
        let want = match self.commanded {
            Move::Drive(amount) | Move::Turn(amount) => amount,
            Move::Lift { to, .. } | Move::Reach { to, .. } => to,
        };
        let what = match self.made {
            Move::Drive(got) => format!(
                "the base stopped after {:.2} m of a {:.2} m drive {}",
                got.abs(),
                want.abs(),
                if want < 0.0 { "back" } else { "ahead" }
            ),
            Move::Turn(got) => format!(
                "the base stopped after {:.0}° of a {:.0}° turn",
                got.to_degrees().abs(),
                want.to_degrees().abs()
            ),
            Move::Lift { to: got, .. } => {
                format!("the carriage stopped at {got:.2} m on its way to {want:.2} m")
            }
            Move::Reach { to: got, .. } => {
                format!("the arm stopped {got:.2} m out on its way to {want:.2} m")
            }
        };
        match &self.error {
            Some(error) => format!("{what} ({error})"),
            None => format!("{what} (its safety stopped it: something was in its way)"),
        }
    }
}

/// Makes `moves`, stopping at the first the robot did not make in full. They are the motions it
/// came by, undone as they were made rather than steered to the poses odometry recorded: a
/// base's own error in a drive or a turn (a wheel a little larger than its maker says) then
/// undoes itself on the way back, where steering by odometry would add it up, and the hand
/// would come back beside the tag.
fn make(robot: &impl TaskRobot, moves: impl Iterator<Item = Move>) -> Result<Made, HalError> {
    let mut made = Vec::new();
    for commanded in moves {
        // A drive or a turn is told as made by odometry, a lift or a reach by its joint.
        let base = |go: &dyn Fn() -> Result<(), HalError>| -> Result<_, HalError> {
            let before = robot.pose_estimate()?;
            let moved = go();
            Ok((as_made(commanded, &before, &robot.pose_estimate()?), moved.err()))
        };
        let (done, error) = match commanded {
            Move::Drive(distance) => base(&|| robot.drive(distance))?,
            Move::Turn(angle) => base(&|| robot.turn(angle))?,
            Move::Lift { from, to } => {
                let lifted = robot.move_to_height(to, f64::INFINITY);
                (Move::Lift { from, to: robot.height()? }, lifted.err())
            }
            Move::Reach { from, to } => {
                let reached = robot.move_to_extension(to, f64::INFINITY);
                (Move::Reach { from, to: robot.extension()? }, reached.err())
            }
        };
        made.push(done);
        let whole = match (commanded, done) {
            (Move::Lift { to, .. }, Move::Lift { to: got, .. })
            | (Move::Reach { to, .. }, Move::Reach { to: got, .. }) => (to - got).abs() < 0.01,
            _ => commanded == done,
        };
        if !whole || error.is_some() {
            return Ok(Made { moves: made, stop: Some(Stop { commanded, made: done, error }) });
        }
    }
    Ok(Made { moves: made, stop: None })
}

/// How far the camera is from the tag at `tag` (odometry frame) with the base at `pose`, metres.
fn range(calibration: &CameraCalibration, pose: &PlanarPose, tag: &Point3<f64>) -> f64 {
    (odom_from_base(pose).inverse() * tag - camera_origin(calibration)).norm()
}

/// The motions in words: "turned 68° back, drove 0.95 m back, lowered the hand to 0.80 m".
fn describe(moves: &[Move]) -> String {
    // What a person would not call a move is left out.
    let said: Vec<String> = moves
        .iter()
        .filter_map(|made| match *made {
            Move::Drive(d) if d.abs() >= 0.01 => {
                Some(format!("drove {:.2} m {}", d.abs(), if d < 0.0 { "back" } else { "ahead" }))
            }
            Move::Turn(a) if a.to_degrees().abs() >= 1.0 => {
                Some(format!("turned {:.0}°", a.to_degrees().abs()))
            }
            Move::Lift { from, to } if (to - from).abs() >= 0.01 => Some(format!(
                "{} the hand to {to:.2} m",
                if to < from { "lowered" } else { "raised" }
            )),
            _ => None,
        })
        .collect();
    said.join(", ")
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector2;

    use std::sync::atomic::{AtomicUsize, Ordering};

    use super::*;
    use crate::behaviors::RobotBody;
    use crate::hal::{ColorCamera, MobileBase, forward_to};
    use crate::navigation::RobotFootprint;
    use crate::sim::{DeviceKind, Room, RoomOptions, SimRobot, head_camera, start_pose_at_angle};
    use crate::task::report::TaskReport;
    use crate::task::trailing::Trailing;

    fn outline() -> Outline {
        Outline::of(&RobotFootprint::default(), &RobotBody::default())
    }

    /// A tag on a wall 2 m ahead of the origin, 1.2 m up; the robot starts at `start`, facing
    /// it, the hand at 0.8 m, and the trail then turns toward a waypoint half a metre out from
    /// the tag, drives there, turns to face the tag, raises the hand to the tag and reaches out
    /// 5 cm.
    fn approach(start: Vector2<f64>) -> (Point3<f64>, Trail, Stance) {
        let tag = Point3::new(2.0, 0.0, 1.2);
        let facing = |at: Vector2<f64>| (tag.y - at.y).atan2(tag.x - at.x);
        let first =
            Stance { base: PlanarPose::new(start, facing(start)), height: 0.8, extension: 0.0 };
        let mut trail = Trail::starting_at(first);
        let waypoint = Vector2::new(1.5, 0.0);
        let toward = waypoint - start;
        let heading = toward.y.atan2(toward.x);
        let mut at = first;
        for made in [
            Move::Turn(heading - facing(start)),
            Move::Drive(toward.norm()),
            Move::Turn(facing(waypoint) - heading),
            Move::Lift { from: 0.8, to: 1.2 },
            Move::Reach { from: 0.0, to: 0.05 },
        ] {
            at = made.after(&at);
            trail.push(made, at);
        }
        (tag, trail, Stance { extension: 0.0, ..at })
    }

    fn seen_from(calibration: &CameraCalibration, trail: &Trail, tag: &Point3<f64>) -> f64 {
        range(calibration, &trail.since_sighting()[0].base, tag)
    }

    fn looked(here: &Stance, plan: &Option<BackOff>) -> PlanarPose {
        let Some(back_off) = plan else { panic!("no back-off") };
        here.base * back_off.looked()
    }

    #[test]
    fn straight_back_where_the_robot_came_straight() {
        let calibration = head_camera(0.25);
        let (tag, trail, here) = approach(Vector2::new(0.5, 0.0));
        let from = seen_from(&calibration, &trail, &tag);
        let plan = plan(&calibration, &here, &tag, from, &trail, &outline());
        let Some(BackOff { way: Way::Straight, moves }) = &plan else { panic!("{plan:?}") };
        assert_eq!(moves.len(), 1);
        assert!((range(&calibration, &looked(&here, &plan), &tag) - from).abs() < 1e-6);
    }

    #[test]
    fn along_the_way_in_where_the_robot_came_from_the_side() {
        let calibration = head_camera(0.25);
        let (tag, trail, here) = approach(Vector2::new(0.9, 0.7));
        let from = seen_from(&calibration, &trail, &tag);
        let outline = outline();
        let plan = plan(&calibration, &here, &tag, from, &trail, &outline);
        let Some(BackOff { way: Way::Retraced { straight }, moves }) = &plan else {
            panic!("{plan:?}")
        };
        assert!(*straight < 0.1, "straight back stays on its way in for {straight:.2} m");
        // Made from here, the motions pass through what it swept to where it saw the tag,
        // the hand lowered first, where it was raised.
        assert_eq!(moves[0], Move::Lift { from: 1.2, to: 0.8 });
        let mut at = here;
        for made in moves {
            let next = made.after(&at);
            assert!(trail.covers(&outline, &between(&at, &next)), "{made:?}");
            at = next;
        }
        let first = trail.since_sighting()[0];
        assert!((at.base.translation.vector - first.base.translation.vector).norm() < 1e-9);
        assert!((at.base.rotation.inverse() * first.base.rotation).angle().abs() < 1e-9);
        assert!((at.height - first.height).abs() < 1e-9);
        let looked = looked(&here, &plan);
        assert!((looked.translation.vector - first.base.translation.vector).norm() < 1e-9);
    }

    /// Phase 3 raised the hand to the tag and then drove 40 cm ahead, the arm's reach short of
    /// it: the hand was never at 0.8 m where it reads. Lowered there, as it used to be before
    /// going back, it would sweep 42 cm of air in front of the base that nothing swept; it is
    /// lowered after the drive is undone, where it was raised.
    #[test]
    fn the_hand_is_lowered_where_it_was_raised() {
        let calibration = head_camera(0.25);
        let (tag, mut trail, raised) = approach(Vector2::new(0.9, 0.7));
        let read = Move::Drive(0.4).after(&raised);
        trail.push(Move::Drive(0.4), read);
        let outline = outline();
        let lowered_here = Move::Lift { from: 1.2, to: 0.8 }.after(&read);
        assert!(!trail.covers(&outline, &between(&read, &lowered_here)));
        let from = seen_from(&calibration, &trail, &tag);
        let plan = plan(&calibration, &read, &tag, from, &trail, &outline);
        let Some(BackOff { way: Way::Retraced { .. }, moves }) = &plan else { panic!("{plan:?}") };
        assert_eq!(moves[..2], [Move::Drive(-0.4), Move::Lift { from: 1.2, to: 0.8 }]);
    }

    /// A simulated robot whose base's next `failing` drives fail partway: each goes 40 % of
    /// the way and its motor controller reports a fault.
    struct FaultyDrive<'a> {
        robot: &'a SimRobot,
        failing: AtomicUsize,
    }

    impl MobileBase for FaultyDrive<'_> {
        fn pose_estimate(&self) -> Result<PlanarPose, HalError> {
            self.robot.pose_estimate()
        }

        fn drive(&self, distance: f64) -> Result<(), HalError> {
            let fails = self
                .failing
                .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |left| left.checked_sub(1));
            if fails.is_ok() {
                self.robot.drive(0.4 * distance)?;
                let reason = "its motor controller faulted".to_owned();
                return Err(HalError::Failed { device: "base", reason });
            }
            self.robot.drive(distance)
        }

        fn turn(&self, angle: f64) -> Result<(), HalError> {
            self.robot.turn(angle)
        }
    }

    forward_to!([] FaultyDrive<'_> => robot:
        ColorCamera, BrightnessCamera, TiltingLaser, RfidReader, Carriage, Arm, Gripper,
        FingerForceTorque, PalmRange);

    /// The robot came to the tag turning 17°, driving 0.8 m and turning to face it; going back
    /// along that way, its drive back fails after 0.32 m of the 0.8 m. Without the check of
    /// each motion as made, the error would end the task with the robot 0.32 m back and turned
    /// away from the tag; it comes back by what it made instead, and says so. Checked on the
    /// simulator's true pose: it ends within 2 cm of where it backed off from.
    /// The trail of [`a_drive_failing_partway_is_undone_as_far_as_it_went`]: the robot, the
    /// trail, the tag and the range it was first seen from.
    fn came_from_the_side() -> (SimRobot, Trail, Point3<f64>, f64) {
        let room = Room::new(RoomOptions::default());
        let start = start_pose_at_angle(room.device(DeviceKind::AdaLightSwitch), 0.0, 1.5);
        let sim = SimRobot::new(room, start, 34);
        let trailing = Trailing::new(&sim).unwrap();
        trailing.saw_the_tag();
        trailing.turn(0.3).unwrap();
        trailing.drive(0.8).unwrap();
        let tag = Point3::new(2.0, 0.0, 1.2);
        let facing = odom_from_base(&trailing.pose_estimate().unwrap()).inverse() * tag;
        trailing.turn(facing.y.atan2(facing.x)).unwrap();
        let trail = trailing.trail();
        let seen_from = seen_from(&sim.calibration(), &trail, &tag);
        drop(trailing);
        (sim, trail, tag, seen_from)
    }

    #[test]
    fn a_drive_failing_partway_is_undone_as_far_as_it_went() {
        let (sim, trail, tag, seen_from) = came_from_the_side();
        let backed_from = sim.state().body.world_from_base;
        let faulty = FaultyDrive { robot: &sim, failing: AtomicUsize::new(1) };
        let mut report = TaskReport::default();
        let phase = report.phase(4, "read the entry, act, ask, record");
        let backing = back_off(&faulty, &tag, seen_from, &trail, &outline(), phase).unwrap();
        assert_eq!(backing, Backing::NoLook);
        let said = phase.lines.join("\n");
        assert!(said.contains("the base stopped after 0.32 m of a 0.80 m drive back"), "{said}");
        assert!(said.contains("(base failed: its motor controller faulted)"), "{said}");
        assert!(said.contains("came back by what it had made (drove 0.32 m ahead"), "{said}");
        let end = sim.state().body.world_from_base;
        let off = (end.translation.vector - backed_from.translation.vector).norm();
        assert!(off < 0.02, "it ended {:.1} cm from where it backed off from", off * 100.0);
        let turned = (end.rotation.inverse() * backed_from.rotation).angle().abs();
        assert!(turned < 2f64.to_radians(), "it ended turned {:.1}°", turned.to_degrees());
    }

    /// As [`a_drive_failing_partway_is_undone_as_far_as_it_went`], and the drive coming back
    /// fails too: the robot stands 19 cm short of where the hand was brought, and the phase
    /// fails saying so rather than reaching from there.
    #[test]
    fn a_robot_stopped_going_and_coming_back_does_not_act() {
        let (sim, trail, tag, seen_from) = came_from_the_side();
        let faulty = FaultyDrive { robot: &sim, failing: AtomicUsize::new(2) };
        let mut report = TaskReport::default();
        let phase = report.phase(4, "read the entry, act, ask, record");
        let backing = back_off(&faulty, &tag, seen_from, &trail, &outline(), phase).unwrap();
        assert_eq!(backing, Backing::Stranded);
        assert!(!phase.ok, "{:?}", phase.lines);
        let said = phase.lines.join("\n");
        assert!(
            said.contains("coming back, the base stopped after 0.13 m of a 0.32 m drive ahead"),
            "{said}"
        );
        assert!(said.contains("is not where the hand was brought and does not act"), "{said}");
    }

    #[test]
    fn no_back_off_where_the_camera_is_as_far_already() {
        let calibration = head_camera(0.25);
        let (tag, trail, here) = approach(Vector2::new(0.5, 0.0));
        let near = range(&calibration, &here.base, &tag);
        assert_eq!(plan(&calibration, &here, &tag, near + 0.005, &trail, &outline()), None);
    }
}
