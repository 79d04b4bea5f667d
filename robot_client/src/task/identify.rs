//! Phase 3 (paper §IV-B.1.b): the tag's position, carried by odometry from phase 2, has drifted;
//! look again where possible, face the tag, bring the closed fingers to about 10 cm from it
//! (stopping on contact), and read the RFID: the strongest tag by a margin, and when two are
//! about as strong, move closer and read again.

use nalgebra::Point3;
use pps_schema::{TagColor, TagSize};

use super::approach::{Look, look};
use super::config::TaskConfig;
use super::drive::{in_base, in_odom, in_view};
use super::report::PhaseReport;
use crate::behaviors::Hand;
use crate::hal::{ColorCamera, Finger, HalError, MobileBase, RfidReader, TiltSweep, TiltingLaser};
use crate::navigation::{ApproachParams, RfidIdentity, identify_tag};
use crate::perception::{tag_color, tag_size};

/// Force that means the fingers bumped into something on the way, newtons.
const BUMP_FORCE: f64 = 2.0;
/// Finger force that means the hand holds something, which it keeps holding, newtons.
const HOLDING_FORCE: f64 = 0.5;
/// How far to move closer when two tags answer about as strongly, metres, and how often.
const CLOSER_STEP: f64 = 0.04;
const CLOSER_TRIES: usize = 2;
/// Half the tilt range of the second look at the tag, radians: from the waypoint, about 10 cm
/// either side of it.
const TAG_SWEEP_HALF: f64 = 0.26;

/// Servoes to the tag (odometry frame, updated when seen again) and reads its RFID; `None`
/// when no tag answered.
pub(crate) fn servo_and_read(
    robot: &(impl Hand + MobileBase + ColorCamera + TiltingLaser + RfidReader),
    tag: &mut Point3<f64>,
    config: &TaskConfig,
    report: &mut PhaseReport,
) -> Result<Option<RfidIdentity>, HalError> {
    look_again(robot, tag, config, report)?;
    let bump = reach_toward(robot, tag, config, report)?;
    read_until_clear(robot, config, bump, report)
}

/// Updates `tag` from a second look where the camera can see it from here, since odometry has
/// drifted on the way; otherwise keeps odometry's.
fn look_again(
    robot: &(impl MobileBase + ColorCamera + TiltingLaser),
    tag: &mut Point3<f64>,
    config: &TaskConfig,
    report: &mut PhaseReport,
) -> Result<(), HalError> {
    match look_from_here(robot, tag, tag, config, &config.approach)? {
        SecondLook::Seen { at: seen, .. } => {
            report.note(format!(
                "saw the tag again, {:.3} m from where odometry put it",
                (seen - *tag).norm()
            ));
            *tag = seen;
        }
        SecondLook::NotFound(_) => report.note("the tag is not in view here; going by odometry"),
        SecondLook::OutOfView => {
            report.note("the tag is below the camera's view here; going by odometry")
        }
    }
    Ok(())
}

/// What a look from where the robot stands made of the tag expected at a point.
pub(super) enum SecondLook {
    /// The tag's centre, odometry frame, what the search said of the red it divided, and the
    /// tag's colour in the picture.
    Seen { at: Point3<f64>, notes: Vec<String>, color: Option<TagColor>, size: Option<TagSize> },
    /// The camera sees the point, but the search took no tag there; why, when it said.
    NotFound(Option<String>),
    /// The point lies outside the camera's view from here.
    OutOfView,
}

/// Looks for the tag expected at `tag` (odometry frame) from where the robot stands, searching
/// with `params` for the tag nearest `around`: the laser swept across `tag` alone, where the
/// camera can see it.
pub(super) fn look_from_here(
    robot: &(impl MobileBase + ColorCamera + TiltingLaser),
    tag: &Point3<f64>,
    around: &Point3<f64>,
    config: &TaskConfig,
    params: &ApproachParams,
) -> Result<SecondLook, HalError> {
    let expected = in_base(robot, tag)?;
    if !in_view(&robot.calibration(), &expected, 0.05) {
        return Ok(SecondLook::OutOfView);
    }
    let sweep = sweep_toward(&config.body.laser, &expected, &config.sweep);
    let Look { image, plan, .. } = look(robot, around, &sweep, params)?;
    match plan.tag.as_ref().map(|s| s.nearest()) {
        Some(seen) => Ok(SecondLook::Seen {
            at: in_odom(robot, &seen.centroid)?,
            color: tag_color(&image, &robot.calibration(), seen, &params.tag),
            size: plan.backing_plane.as_ref().and_then(|plane| {
                tag_size(&image, &robot.calibration(), seen, &params.tag, &plane.normal)
            }),
            notes: plan.tag_notes,
        }),
        None => Ok(SecondLook::NotFound(plan.tag_notes.last().cloned())),
    }
}

/// Faces the tag, hand at its height, fingers closed and pointed at it, and brings them to
/// `config.servo_distance` from it, stopping on contact; returns the force that means a bump.
pub(super) fn reach_toward(
    robot: &(impl Hand + MobileBase),
    tag: &Point3<f64>,
    config: &TaskConfig,
    report: &mut PhaseReport,
) -> Result<f64, HalError> {
    let here = in_base(robot, tag)?;
    robot.turn(here.y.atan2(here.x))?;
    let here = in_base(robot, tag)?;
    // A held object loads the fingers already: a bump is force beyond that.
    let held = robot
        .wrench(Finger::Left)?
        .force_magnitude()
        .max(robot.wrench(Finger::Right)?.force_magnitude());
    let bump = held + BUMP_FORCE;
    robot.move_to_height(here.z, bump)?;
    if held < HOLDING_FORCE {
        robot.set_opening(0.0, f64::INFINITY)?;
    }
    let body = &config.body;
    let mut extension = here.x - config.servo_distance - body.palm_ahead - body.finger_length;
    // The arm keeps room to move closer when the read is ambiguous; beyond that, or behind its
    // start, the base covers the difference.
    let spare = CLOSER_TRIES as f64 * CLOSER_STEP;
    if !(0.0..=robot.farthest() - spare).contains(&extension) {
        let by = if extension < 0.0 { extension } else { extension - 0.1 };
        robot.drive(by)?;
        extension -= by;
    }
    let reached = robot.move_to_extension(extension.max(0.0), bump)?;
    report.note(format!(
        "faced the tag, hand at {:.2} m, fingers {:.2} m from the tag{}",
        here.z,
        config.servo_distance + (extension - reached).max(0.0),
        if reached < extension - 1e-3 { " (stopped by contact)" } else { "" }
    ));
    Ok(bump)
}

/// Reads the RFID; while two tags answer about as strongly, moves the fingers closer (never
/// harder than `bump`) and reads again.
fn read_until_clear(
    robot: &(impl Hand + RfidReader),
    config: &TaskConfig,
    bump: f64,
    report: &mut PhaseReport,
) -> Result<Option<RfidIdentity>, HalError> {
    let mut identity = read(robot, config)?;
    for _ in 0..CLOSER_TRIES {
        let Some(RfidIdentity::Ambiguous { strongest, runner_up }) = &identity else { break };
        report.note(format!(
            "ambiguous: {} at {:.1} dBm and {} at {:.1} dBm; moving {CLOSER_STEP} m closer",
            strongest.epc, strongest.rssi_dbm, runner_up.epc, runner_up.rssi_dbm
        ));
        let at = robot.extension()?;
        robot.move_to_extension(at + CLOSER_STEP, bump)?;
        identity = read(robot, config)?;
    }
    match &identity {
        Some(RfidIdentity::Identified(signal)) => report.note(format!(
            "RFID: {} at {:.1} dBm ({} reads)",
            signal.epc, signal.rssi_dbm, signal.reads
        )),
        Some(RfidIdentity::Ambiguous { strongest, runner_up }) => report.note(format!(
            "RFID still ambiguous: {} at {:.1} dBm, {} at {:.1} dBm",
            strongest.epc, strongest.rssi_dbm, runner_up.epc, runner_up.rssi_dbm
        )),
        None => report.fail_advising(
            "no RFID tag answered",
            "it reached the red it saw, but no tag answered there; if something red is beside \
             the tag, move it away; if not, the tag may be worn: replace it on the tag's page",
        ),
    }
    Ok(identity)
}

/// A sweep in `usual`'s steps, centred on the tilt that points the laser at `point` (base
/// frame). From the waypoint the usual sweep can cut a high tag in half, and half a tag's points
/// put its centre centimetres off: enough to press the wrong half of a rocker switch.
fn sweep_toward(laser: &Point3<f64>, point: &Point3<f64>, usual: &TiltSweep) -> TiltSweep {
    // Positive tilt turns the scan plane's forward edge down.
    let tilt = -(point.z - laser.z).atan2(point.x - laser.x);
    TiltSweep { from: tilt - TAG_SWEEP_HALF, to: tilt + TAG_SWEEP_HALF, step: usual.step }
}

fn read(robot: &impl RfidReader, config: &TaskConfig) -> Result<Option<RfidIdentity>, HalError> {
    let mut reads = Vec::new();
    for _ in 0..config.rfid_rounds {
        reads.extend(robot.inventory()?);
    }
    Ok(identify_tag(&reads, config.rfid_margin_db))
}
