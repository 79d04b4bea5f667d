//! The four phases in order, ending in a trial recorded through the registry client.

use nalgebra::Point3;
use pps_schema::{Epc, Outcome, StartPose, Trial};
use uuid::Uuid;

use super::act::{ActionChoice, choose_action, run_behavior};
use super::approach::approach_tag;
use super::drive::{drive_toward, in_base, in_odom};
use super::identify::servo_and_read;
use super::report::{PhaseReport, TaskReport};
use crate::behaviors::{DropGeometry, ForceRecorder, Hand, RobotBody};
use crate::hal::{
    BrightnessCamera, Clock, ColorCamera, MobileBase, Operator, RfidReader, TiltSweep, TiltingLaser,
};
use crate::navigation::{ApproachParams, RfidIdentity};
use crate::perception::{HsvThresholds, covering_colour, describe_colour};
use crate::registry::{RegistryClient, Source};

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

    // Phase 2: find the tag and the surface behind it; drive to the waypoint.
    let phase = report.phase(2, "approach the tag perpendicular to its surface");
    let config = &with_known_tag_colours(config, registry, phase);
    let Some(mut tag) =
        approach_tag(robot, operator, &target, &config.sweep, &config.approach, phase)?
    else {
        return Ok(report);
    };

    // Phase 3: fingers to 10 cm, read the RFID.
    let phase = report.phase(3, "servo to the tag and read its RFID");
    let Some(identity) = servo_and_read(robot, &mut tag, config, phase)? else {
        return Ok(report);
    };

    // Phase 4: the registry's entry, the action, the behaviour, the person, the trial.
    let phase = report.phase(4, "read the entry, act, ask, record");
    let tag_here = in_base(robot, &tag)?;
    let epc = match identity {
        RfidIdentity::Identified(signal) => signal.epc,
        RfidIdentity::Ambiguous { strongest, runner_up } => {
            // Cross-check with where the tag was seen: the entry whose height matches it.
            let mut best = (f64::INFINITY, strongest.epc.clone());
            for epc in [strongest.epc, runner_up.epc] {
                if let Ok(fetched) = registry.effective_entry(&epc).await
                    && let Some(height) = fetched.entry.entry.properties.height
                {
                    let off = (height - tag_here.z).abs();
                    if off < best.0 {
                        best = (off, epc);
                    }
                }
            }
            phase.note(format!(
                "took {} by the entries' heights against the tag seen at {:.2} m",
                best.1, tag_here.z
            ));
            best.1
        }
    };
    report.epc = Some(epc.clone());
    act(robot, operator, registry, clock, config, &epc, tag_here, &mut report).await?;
    Ok(report)
}

/// The task's settings with the tag search looking for the colours this robot's camera sees the
/// registry's tags in (their entries' `color_segmentation`, merged for this robot).
fn with_known_tag_colours(
    config: &TaskConfig,
    registry: &RegistryClient,
    phase: &mut PhaseReport,
) -> TaskConfig {
    let known = registry.known_entries();
    let colours = known.iter().filter_map(|e| e.entry.properties.color_segmentation());
    let colour = covering_colour(colours.clone());
    let mut config = config.clone();
    match HsvThresholds::new(&colour) {
        Ok(thresholds) => {
            let from = match colours.count() {
                0 => format!("the paper's red: none of {} known tags gives a colour", known.len()),
                n => format!("the colours of {n} of {} known tags", known.len()),
            };
            phase.note(format!("looking for {} ({from})", describe_colour(&colour)));
            config.approach.tag.thresholds = thresholds;
        }
        Err(error) => phase.note(format!(
            "the entries' colours cannot be used ({error}); looking for the default red"
        )),
    }
    config
}

#[allow(clippy::too_many_arguments)]
async fn act(
    robot: &impl TaskRobot,
    operator: &dyn Operator,
    registry: &RegistryClient,
    clock: &dyn Clock,
    config: &TaskConfig,
    epc: &Epc,
    tag: Point3<f64>,
    report: &mut TaskReport,
) -> anyhow::Result<()> {
    let phase = report.phases.last_mut().expect("phase 4 started");
    let fetched = match registry.effective_entry(epc).await {
        Ok(fetched) => fetched,
        Err(error) => {
            phase.fail(format!("no entry for {epc}: {error}"));
            return Ok(());
        }
    };
    let entry = &fetched.entry.entry;
    phase.note(format!(
        "entry: {} ({}), revision {}, {}",
        entry.properties.name,
        entry.properties.kind.as_deref().unwrap_or("no type"),
        fetched.entry.revision,
        match fetched.source {
            Source::Registry => "read from the registry",
            Source::Revalidated => "cached, confirmed current by the registry",
            Source::Fresh => "cached, current by the change feed",
            Source::Offline => "cached; the registry is unreachable",
        }
    ));
    let Some(choice) = choose_action(entry, operator)? else {
        phase.fail(format!(
            "the entry offers {} actions; the interface chooses between one or two",
            entry.actions.len()
        ));
        return Ok(());
    };
    let action = choice.action().to_owned();
    match &choice {
        ActionChoice::Only(a) => phase.note(format!("one action: {a}")),
        ActionChoice::Asked { choice, action } => {
            phase.note(format!("asked the person: they pointed {choice:?}, meaning {action}"))
        }
    }
    if let Some(unavailable) = fetched.entry.unavailable_actions.iter().find(|u| u.action == action)
    {
        phase.fail(format!("{action} is unavailable to this robot: {}", unavailable.reason));
        return Ok(());
    }
    let Some((key, spec)) = entry.behavior_for(&action) else {
        phase.fail(format!("{action} names no behaviour in the entry"));
        return Ok(());
    };
    report.action = Some(action.clone());
    report.behavior = Some(key.to_owned());

    let started = clock.now();
    let forces = ForceRecorder::new(robot, clock, started);
    let drop = DropGeometry { tag, sweep: config.drop_sweep, body: config.body, seed: 7 };
    let result = run_behavior(robot, &spec.params, &entry.properties, &action, &drop, forces);
    let finished = clock.now();
    let phase = report.phases.last_mut().expect("phase 4 started");
    let (outcome, detector, measurements, forces) = match result {
        Ok(behavior) => {
            phase.note(format!("{key} ({}):", spec.kind()));
            for step in &behavior.steps {
                phase.note(format!("  {step}"));
            }
            (behavior.outcome, behavior.detector, behavior.measurements, behavior.forces)
        }
        Err(error) => {
            phase.note(format!("{key} failed: {error}"));
            let mut detector = serde_json::Map::new();
            detector.insert("error".into(), error.to_string().into());
            (Outcome::Error, detector, serde_json::Map::new(), Vec::new())
        }
    };
    let mut measurements = measurements;
    if let Some(task) = config.task {
        measurements.insert("task".into(), task.to_string().into());
    }
    let confirmed = operator.confirm_success()?;
    phase.note(format!(
        "the detector says {}; asked the person: {}",
        outcome.as_str(),
        match confirmed {
            Some(true) => "it worked",
            Some(false) => "it did not work",
            None => "no answer",
        }
    ));
    let trial = Trial {
        id: Uuid::new_v4(),
        epc: epc.clone(),
        robot: registry.robot().clone(),
        action,
        behavior: key.to_owned(),
        started_at: started,
        finished_at: finished.max(started),
        outcome,
        confirmed,
        detector,
        forces,
        measurements,
        start_pose: config.start_pose,
        received_at: None,
        seq: None,
    };
    let flushed = registry.record_trial(&trial).await?;
    report.outcome = Some(outcome);
    report.confirmed = confirmed;
    report.trial = Some(trial.id);
    report.waiting_upload = flushed.remaining;
    Ok(())
}
