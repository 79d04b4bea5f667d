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
use super::trail::{Trail, between};
use crate::hal::{CameraCalibration, HalError, MobileBase, PlanarPose};
use crate::navigation::RobotFootprint;

/// A range this near the one the tag was first seen from is the same, metres: the flash's light
/// on the tag changes by 2 % per centimetre at 1 m.
const SAME_RANGE: f64 = 0.01;

/// The legs of a drive or a turn shorter than these are not made, metres and radians.
const TINY_DRIVE: f64 = 0.001;
const TINY_TURN: f64 = 0.001;

/// Which way the robot backed off.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Way {
    /// Straight back the whole way: it stays on the ground the base came over.
    Straight,
    /// Back along the way it came to where it first saw the tag: straight back would have left
    /// that ground after `straight` metres.
    Retraced { straight: f64 },
}

/// Where the robot went to look: the poses it passed, odometry frame, from where the hand was
/// brought to where it looked.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct BackOff {
    pub way: Way,
    legs: Vec<PlanarPose>,
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
    follow(robot, &back_off.legs[1..])?;
    let last = back_off.legs.last().expect("a back-off has legs");
    let (from, went) = (range(&calibration, last, tag), travelled(&back_off.legs));
    phase.note(match back_off.way {
        Way::Straight => format!(
            "backed off {went:.2} m straight, over ground it came by, to look from {from:.2} m, \
             as far as the tag was first seen from: its colour was learned at that range"
        ),
        Way::Retraced { straight } => format!(
            "backed off along its way in ({}) to where it first saw the tag, to look from \
             {from:.2} m: straight back would have left the ground it came over after \
             {straight:.2} m",
            describe(&back_off.legs)
        ),
    });
    Ok(Some(back_off))
}

/// Drives back to where the hand was brought before the back-off, the way it backed off.
pub(super) fn come_back(
    robot: &impl TaskRobot,
    back_off: &BackOff,
    phase: &mut PhaseReport,
) -> Result<(), HalError> {
    let back: Vec<PlanarPose> = back_off.legs.iter().rev().skip(1).copied().collect();
    follow(robot, &back)?;
    phase.note("came back the way it backed off");
    Ok(())
}

/// Where to back off to from `here`, as [`back_off`] chooses: the poses to pass, `here` first.
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
        return Some(BackOff { way: Way::Straight, legs: vec![*here, straight_back(back)] });
    }
    // Where it stood when it first saw the tag, it saw it from that range.
    // It looks as it did then, facing the way it faced: only the colour and size it looks for
    // differ from that look.
    let legs = std::iter::once(*here).chain(trail.since_sighting().iter().rev().copied());
    Some(BackOff { way: Way::Retraced { straight }, legs: legs.collect() })
}

/// Makes the base pass each of `poses` (odometry frame) in turn, each reached from the last by
/// a drive straight ahead or back and a turn in place, as the legs of a trail are.
fn follow(base: &impl MobileBase, poses: &[PlanarPose]) -> Result<(), HalError> {
    for to in poses {
        let ahead = (base.pose_estimate()?.inverse() * to).translation.x;
        if ahead.abs() > TINY_DRIVE {
            base.drive(ahead)?;
        }
        let turn = (base.pose_estimate()?.inverse() * to).rotation.angle();
        if turn.abs() > TINY_TURN {
            base.turn(turn)?;
        }
    }
    Ok(())
}

/// How far the camera is from the tag at `tag` (odometry frame) with the base at `pose`, metres.
fn range(calibration: &CameraCalibration, pose: &PlanarPose, tag: &Point3<f64>) -> f64 {
    (odom_from_base(pose).inverse() * tag - camera_origin(calibration)).norm()
}

/// How far the base drives along `legs`, metres.
fn travelled(legs: &[PlanarPose]) -> f64 {
    legs.windows(2).map(|leg| (leg[1].translation.vector - leg[0].translation.vector).norm()).sum()
}

/// The legs in words: "turned 23° back, drove 0.80 m back".
fn describe(legs: &[PlanarPose]) -> String {
    let mut said = Vec::new();
    for leg in legs.windows(2) {
        let distance = (leg[1].translation.vector - leg[0].translation.vector).norm();
        let angle = (leg[0].rotation.inverse() * leg[1].rotation).angle().to_degrees();
        // What a person would not call a move is left out.
        if distance >= 0.01 {
            said.push(format!("drove {distance:.2} m back"));
        }
        if angle.abs() >= 1.0 {
            said.push(format!("turned {:.0}° back", angle.abs()));
        }
    }
    said.join(", ")
}
