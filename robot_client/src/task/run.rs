//! The four phases in order, ending in a trial recorded through the registry client.

use pps_schema::{Purpose, StartPose};
use uuid::Uuid;

use super::approach::{Look, drive_to_waypoint, look_for_tag_and_surface};
use super::drive::{camera_origin, drive_toward, in_base, in_odom};
use super::identify::servo_and_read;
use super::known_tags::{ColourSource, search_for_known_tags};
use super::perform::{Acting, FoundTag, act, settle_epc};
use super::report::{PhaseReport, TaskReport};
use super::trailing::Trailing;
use crate::behaviors::{Hand, RobotBody};
use crate::hal::{
    BrightnessCamera, Clock, ColorCamera, MobileBase, Operator, RfidReader, TiltSweep, TiltingLaser,
};
use crate::navigation::{ApproachParams, RfidIdentity};
use crate::perception::{tag_color, tag_size};
use crate::registry::RegistryClient;

/// Everything the task needs of a robot.
pub trait TaskRobot:
    Hand + MobileBase + ColorCamera + TiltingLaser + RfidReader + BrightnessCamera
{
}

impl<T: Hand + MobileBase + ColorCamera + TiltingLaser + RfidReader + BrightnessCamera> TaskRobot
    for T
{
}

/// The task's settings: the paper's numbers, and this robot's body and sensors.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskConfig {
    pub body: RobotBody,
    /// Phase 1 drives until the base's front is this near the pointed location (paper: 1.0 m).
    pub near_enough: f64,
    /// Phase 2's perception and waypoint (50 cm out).
    pub approach: ApproachParams,
    /// The laser sweep for finding the tag, and the steeper one for a container's top.
    pub sweep: TiltSweep,
    pub drop_sweep: TiltSweep,
    /// Phase 3 brings the fingertips this near the tag (paper: 10 cm).
    pub servo_distance: f64,
    /// Inventory rounds per RFID read, and the margin by which the strongest tag must win, dB.
    pub rfid_rounds: usize,
    pub rfid_margin_db: f64,
    /// Where the experiment put the robot, for the trial record (the robot has no map).
    pub start_pose: Option<StartPose>,
    /// The registry task this run does, recorded in the trial's `measurements.task`.
    pub task: Option<Uuid>,
    /// Why the task is done: an experiment's trials are kept out of the registry's success
    /// rates, reliability and learning.
    pub purpose: Purpose,
    /// Send the trial with a picture of what the camera saw around the tag (DESIGN §10).
    pub picture: bool,
}

impl Default for TaskConfig {
    fn default() -> Self {
        Self {
            body: RobotBody::default(),
            near_enough: 1.0,
            approach: ApproachParams::default(),
            sweep: TiltSweep {
                from: -20f64.to_radians(),
                to: 35f64.to_radians(),
                step: 0.25f64.to_radians(),
            },
            drop_sweep: TiltSweep { from: 0.0, to: 65f64.to_radians(), step: 0.5f64.to_radians() },
            servo_distance: 0.10,
            rfid_rounds: 5,
            rfid_margin_db: 3.0,
            start_pose: None,
            task: None,
            purpose: Purpose::Use,
            picture: true,
        }
    }
}

/// Runs the task once: the operator points, the robot acts, and the trial goes to the registry
/// (through the outbox, so it is kept while the registry is unreachable).
pub async fn run_task(
    robot: &impl TaskRobot,
    operator: &dyn Operator,
    registry: &RegistryClient,
    clock: &dyn Clock,
    config: &TaskConfig,
) -> anyhow::Result<TaskReport> {
    let mut report = TaskReport::default();

    // Phase 1: toward the pointed location.
    let phase = report.phase(1, "drive toward the pointed location");
    let Some(pointed) = operator.pointed_target()? else {
        phase.fail("nobody pointed at anything");
        return Ok(report);
    };
    let target = in_odom(robot, &pointed)?;
    drive_toward(robot, &robot.calibration(), &config.body, &target, config.near_enough, phase)?;

    // Phase 2: find the tag and the surface behind it; drive to the waypoint. From here on the
    // base keeps the trail of where it went, the only ground it may later back off over.
    let trailing = Trailing::new(robot)?;
    let robot = &trailing;
    let phase = report.phase(2, "approach the tag perpendicular to its surface");
    registry.refresh_announced().await;
    let (tag, notes) = search_for_known_tags(
        &config.approach.tag,
        &registry.known_entries(),
        ColourSource::KnownTags,
    );
    for note in notes {
        phase.note(note);
    }
    let mut config = config.clone();
    config.approach.tag = tag;
    let config = &config;
    let seen =
        look_for_tag_and_surface(robot, operator, &target, &config.sweep, &config.approach, phase)?;
    robot.saw_the_tag();
    let Some(mut tag) = drive_to_waypoint(robot, &seen.plan, phase)? else {
        return Ok(report);
    };
    let picture = config.picture.then(|| picture_of(robot, &seen, config, phase)).flatten();
    let tag_color = seen.plan.tag.as_ref().and_then(|t| {
        tag_color(&seen.image, &robot.calibration(), t.nearest(), &config.approach.tag)
    });
    let camera = camera_origin(&robot.calibration());
    let seen_from = seen.plan.tag.as_ref().map_or(0.0, |t| (t.nearest().centroid - camera).norm());
    let tag_size =
        (seen.plan.tag.as_ref().zip(seen.plan.backing_plane.as_ref())).and_then(|(t, plane)| {
            let (calibration, search) = (robot.calibration(), &config.approach.tag);
            tag_size(&seen.image, &calibration, t.nearest(), search, &plane.normal)
        });

    // Phase 3: fingers to 10 cm, read the RFID.
    let phase = report.phase(3, "servo to the tag and read its RFID");
    let Some(identity) = servo_and_read(robot, &mut tag, config, phase)? else {
        return Ok(report);
    };

    // Phase 4: the registry's entry, the action, the behaviour, the person, the trial.
    let phase = report.phase(4, "read the entry, act, ask, record");
    let at = in_base(robot, &tag)?;
    // Only a read that names one tag says the look's pixels and points were that tag.
    let one_tag = matches!(identity, RfidIdentity::Identified(_));
    let epc = settle_epc(identity, &at, registry, phase).await;
    report.epc = Some(epc.clone());
    let acting = Acting { robot, operator, registry, clock, config, picture: picture.as_deref() };
    let (color, size) = (tag_color.filter(|_| one_tag), tag_size.filter(|_| one_tag));
    let trail = robot.trail();
    let found = FoundTag { epc, at, seen_from, pointed: seen.target, color, size, trail };
    act(&acting, found, &mut report).await?;
    Ok(report)
}

/// The picture the trial is sent with: the look that led to the waypoint, drawn as Fig. 5.
fn picture_of(
    robot: &impl TaskRobot,
    seen: &Look,
    config: &TaskConfig,
    phase: &mut PhaseReport,
) -> Option<Vec<u8>> {
    let footprint = &config.approach.footprint;
    match crate::picture::trial_picture(&seen.image, &robot.calibration(), &seen.plan, footprint) {
        Ok(picture) => Some(picture),
        Err(error) => {
            phase.note(format!("no picture for the trial: it could not be encoded ({error})"));
            None
        }
    }
}
