//! The four phases in order, ending in a trial recorded through the registry client.

use super::approach::{Look, drive_to_waypoint, look_for_tag_and_surface};
use super::config::TaskConfig;
use super::drive::{camera_origin, drive_toward, in_base, in_odom};
use super::identify::servo_and_read;
use super::known_tags::{ColourSource, search_for_known_tags, search_in_the_registered_colour};
use super::perform::{Acting, FoundTag, act, settle_epc};
use super::report::{PhaseReport, TaskReport};
use super::task_robot::TaskRobot;
use super::trailing::Trailing;
use crate::hal::{Clock, ColorCamera, Operator};
use crate::navigation::RfidIdentity;
use crate::perception::{tag_color, tag_size};
use crate::registry::RegistryClient;

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
    let known = registry.known_entries();
    let (tag, notes) = search_for_known_tags(&config.approach.tag, &known, ColourSource::KnownTags);
    for note in notes {
        phase.note(note);
    }
    let mut config = config.clone();
    config.approach.tag = tag;
    let mut seen =
        look_for_tag_and_surface(robot, operator, &target, &config.sweep, &config.approach, phase)?;
    if seen.plan.saw_nothing_red()
        && let Some((registered, note)) =
            search_in_the_registered_colour(&config.approach.tag, &known)
    {
        phase.note(note);
        config.approach.tag = registered;
        seen = look_for_tag_and_surface(
            robot,
            operator,
            &target,
            &config.sweep,
            &config.approach,
            phase,
        )?;
    }
    let config = &config;
    robot.saw_the_tag();
    let sized = !config.approach.tag.home_tags.is_empty();
    let Some(mut tag) = drive_to_waypoint(robot, &seen.plan, sized, phase)? else {
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
