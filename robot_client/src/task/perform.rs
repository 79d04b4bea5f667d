//! Phase 4 step by step (paper §IV-B): the tag's EPC settled, the registry's entry read, the
//! action and its behaviour chosen, the behaviour performed, the person asked, and the trial
//! recorded through the outbox.

use nalgebra::Point3;
use pps_schema::{
    BehaviorSpec, EffectiveEntry, Epc, Outcome, Properties, TagColor, TagSize, Trial,
};
use serde_json::{Map, Value};
use time::OffsetDateTime;
use uuid::Uuid;

use super::act::{ActionChoice, choose_action, run_behavior};
use super::back_off::{Backing, back_off, come_back};
use super::config::TaskConfig;
use super::drive::{in_base, in_odom};
use super::identify::{SecondLook, look_from_here, reach_toward};
use super::known_tags::{ColourSource, search_for_this_tag};
use super::outline::Outline;
use super::report::{PhaseReport, TaskReport};
use super::task_robot::TaskRobot;
use super::trail::Trail;
use crate::behaviors::{DropGeometry, ForceRecorder};
use crate::hal::{Clock, HalError, Operator};
use crate::navigation::{ApproachParams, RfidIdentity};
use crate::registry::{Fetched, RegistryClient, Source};

/// Who takes part in phase 4, and the settings it runs by.
pub(super) struct Acting<'a, R> {
    pub robot: &'a R,
    pub operator: &'a dyn Operator,
    pub registry: &'a RegistryClient,
    pub clock: &'a dyn Clock,
    pub config: &'a TaskConfig,
    /// What the camera saw around the tag (PNG), sent with the trial.
    pub picture: Option<&'a [u8]>,
}

/// The tag phase 4 acts on: its EPC, and where it was seen (base frame, metres).
pub(super) struct FoundTag {
    pub epc: Epc,
    pub at: Point3<f64>,
    /// How far from the camera it was when first found, metres: the range its colour, sent
    /// with the trial and learned from, was seen at.
    pub seen_from: f64,
    /// Where the person pointed, odometry frame: a red region larger than the tag is divided
    /// around it, as it was when the tag was first found.
    pub pointed: Point3<f64>,
    /// The tag's colour where it was first found, sent with the trial: the EPC read since says
    /// the pixels were this tag's, unless the look after the read finds it elsewhere.
    pub color: Option<TagColor>,
    /// The tag's size on its surface in that look, sent with the trial on the same condition.
    pub size: Option<TagSize>,
    /// Where the base went since it first looked for the tag: the ground it may back off over.
    pub trail: Trail,
}

/// How far the tag, seen again after its read, may lie from where the hand was brought for the
/// hand to stay there, metres: a rocker's press meant 2 cm above its middle then still lands a
/// centimetre above, clear of its 6 mm dead band, and the other behaviours align against the tag
/// themselves.
const HAND_STAYS_WITHIN: f64 = 0.01;

/// How finely a look from the range the tag was first seen from places it, metres: at 1.2 m a
/// pixel of the camera and a step of the laser each span about 5 mm, and a tag seen from the
/// side of a first sighting shows a few of them less.
const FAR_LOOK_PRECISION: f64 = 0.02;

/// The action chosen and the behaviour the entry names for it.
struct Chosen<'e> {
    action: String,
    key: &'e str,
    spec: &'e BehaviorSpec,
}

/// What the behaviour did, and when.
struct Performed {
    started: OffsetDateTime,
    finished: OffsetDateTime,
    outcome: Outcome,
    detector: Map<String, Value>,
    measurements: Map<String, Value>,
    forces: Vec<pps_schema::ForceSample>,
}

/// The EPC the reads name; when two tags read alike, the one whose entry's height matches where
/// the tag was seen.
pub(super) async fn settle_epc(
    identity: RfidIdentity,
    at: &Point3<f64>,
    registry: &RegistryClient,
    phase: &mut PhaseReport,
) -> Epc {
    match identity {
        RfidIdentity::Identified(signal) => signal.epc,
        RfidIdentity::Ambiguous { strongest, runner_up } => {
            let mut best = (f64::INFINITY, strongest.epc.clone());
            for epc in [strongest.epc, runner_up.epc] {
                if let Ok(fetched) = registry.effective_entry(&epc).await
                    && let Some(height) = fetched.entry.entry.properties.height
                {
                    let off = (height - at.z).abs();
                    if off < best.0 {
                        best = (off, epc);
                    }
                }
            }
            phase.note(format!(
                "took {} by the entries' heights against the tag seen at {:.2} m",
                best.1, at.z
            ));
            best.1
        }
    }
}

/// Phase 4 on the tag found, noted in the report's last phase. It stops, failing the phase,
/// where the entry leaves the robot nothing to do.
pub(super) async fn act(
    acting: &Acting<'_, impl TaskRobot>,
    mut tag: FoundTag,
    report: &mut TaskReport,
) -> anyhow::Result<()> {
    let phase = report.phases.last_mut().expect("phase 4 started");
    let Some(fetched) = read_entry(acting.registry, &tag.epc, phase).await else {
        return Ok(());
    };
    let Some(chosen) = choose_behavior(&fetched, acting.operator, phase)? else {
        return Ok(());
    };
    report.action = Some(chosen.action.clone());
    report.behavior = Some(chosen.key.to_owned());
    let phase = report.phases.last_mut().expect("phase 4 started");
    if !look_knowing_the_tag(acting, &fetched.entry, &mut tag, phase)? {
        return Ok(());
    }
    let performed = perform(acting, &chosen, &fetched.entry.entry.properties, tag.at, phase);
    let confirmed = ask_the_person(acting.operator, performed.outcome, phase)?;
    let trial = trial_record(acting, &tag, chosen, performed, confirmed);
    let flushed = acting.registry.record_trial_with_picture(&trial, acting.picture).await?;
    report.outcome = Some(trial.outcome);
    report.confirmed = confirmed;
    report.trial = Some(trial.id);
    report.waiting_upload = flushed.remaining;
    Ok(())
}

/// The entry for `epc` as it applies to this robot, noting where it came from; `None`, failing
/// the phase, when there is none to be had.
async fn read_entry(
    registry: &RegistryClient,
    epc: &Epc,
    phase: &mut PhaseReport,
) -> Option<Fetched> {
    let fetched = match registry.effective_entry(epc).await {
        Ok(fetched) => fetched,
        Err(error) => {
            phase.fail(format!("no entry for {epc}: {error}"));
            return None;
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
    Some(fetched)
}

/// Looks for the tag again now that its entry says what it is: in its own learned colour and at
/// its own registered size, which a neighbouring wooden or red surface joins less often than
/// the household's colour and its largest tag's size did before the read. It looks from the
/// range the tag was first seen from, backing off over the ground it came over
/// ([`back_off`]). The hand is brought to what that look finds; where it finds nothing, the
/// camera cannot see the tag, or the base was stopped on its way to look, the robot acts where
/// the tag was first seen. `false`, failing the phase, when the base was stopped and could not
/// come back to where the hand was brought.
fn look_knowing_the_tag(
    acting: &Acting<'_, impl TaskRobot>,
    entry: &EffectiveEntry,
    tag: &mut FoundTag,
    phase: &mut PhaseReport,
) -> Result<bool, HalError> {
    let Acting { robot, config, .. } = *acting;
    let search = search_for_this_tag(&config.approach.tag, entry, ColourSource::KnownTags);
    if !search.differs {
        phase.note(format!(
            "its entry tells no more than the look before the read ({}): acting where the tag \
             was first seen",
            search.with
        ));
        return Ok(true);
    }
    for note in search.notes {
        phase.note(note);
    }
    let first = in_odom(robot, &tag.at)?;
    let outline = Outline::of(&config.approach.footprint, &config.body);
    let backed = match back_off(robot, &first, tag.seen_from, &tag.trail, &outline, phase)? {
        Backing::Stayed => None,
        Backing::Went(backed) => Some(backed),
        Backing::NoLook => {
            // Back by odometry where the hand was brought: the hand goes to the tag again.
            reach_again(robot, tag, config, phase)?;
            return Ok(true);
        }
        Backing::Stranded => return Ok(false),
    };
    let params = ApproachParams { tag: search.params, ..config.approach.clone() };
    let look = look_from_here(robot, &first, &tag.pointed, config, &params)?;
    let moved = backed.is_some();
    // Where the hand was brought, base frame then and again once the robot is back.
    let act_at = match look {
        SecondLook::Seen { at: seen, notes, color, size } => {
            for note in notes {
                phase.note(note);
            }
            let here = in_base(robot, &seen)?;
            let seen = backed.as_ref().map_or(here, |backed| backed.seen_from_the_hand(&here));
            let off = (seen - tag.at).norm();
            // The tag read lies within what was first taken for it, which reached no farther
            // from its middle than the search before the read allowed: a tag farther off, seen
            // from where the robot looked (at a side approach's first sighting, obliquely), is
            // another red thing.
            let reach = config.approach.tag.max_tag_radius;
            if off > reach {
                phase.note(format!(
                    "looked again with {}: took a tag {:.1} cm from where the tag was first \
                     seen, farther than what was first taken for it could reach ({:.0} cm): \
                     not the tag read; acting where it was first seen",
                    search.with,
                    off * 100.0,
                    reach * 100.0
                ));
                moved.then_some(tag.at)
            } else {
                // From afar the look tells the tag's place less finely than phase 3's from
                // the hand did: where it agrees within that, the nearer look's point stands.
                let agrees = if moved { FAR_LOOK_PRECISION } else { HAND_STAYS_WITHIN };
                let stays = off <= agrees;
                phase.note(format!(
                    "looked again with {}: the tag is {:.1} cm from where it was first seen; {}",
                    search.with,
                    off * 100.0,
                    if stays { "the hand stays" } else { "acting there" }
                ));
                // Found elsewhere, what was first taken for the tag was not only the tag: its
                // colour would teach the registry the wood or the box beside it. This look was
                // taken from the same range, so its colour is as comparable.
                // A read that did not name one tag sends neither, whatever this look saw.
                if off > HAND_STAYS_WITHIN && tag.color.is_some() && color.is_some() {
                    phase.note("the trial carries the tag's colour and size as this look saw them");
                    tag.color = color;
                    tag.size = size;
                }
                match (stays, moved) {
                    (false, _) => Some(seen),
                    (true, true) => Some(tag.at),
                    (true, false) => None,
                }
            }
        }
        SecondLook::NotFound(why) => {
            phase.note(format!(
                "looked again with {} and took no tag{}; acting where it was first seen",
                search.with,
                why.map(|why| format!(" ({why})")).unwrap_or_default()
            ));
            moved.then_some(tag.at)
        }
        SecondLook::OutOfView => {
            phase.note("the camera cannot see the tag from here; acting where it was first seen");
            moved.then_some(tag.at)
        }
    };
    if let Some(at) = act_at {
        // Back where the hand was brought before, so the behaviour has the arm's travel.
        if let Some(backed) = &backed
            && !come_back(robot, backed, phase)?
        {
            return Ok(false);
        }
        tag.at = at;
        reach_again(robot, tag, config, phase)?;
    }
    Ok(true)
}

/// Brings the hand to the tag at `tag.at` again (base frame where the hand was brought, and
/// where the base stands again).
fn reach_again(
    robot: &impl TaskRobot,
    tag: &mut FoundTag,
    config: &TaskConfig,
    phase: &mut PhaseReport,
) -> Result<(), HalError> {
    let at = in_odom(robot, &tag.at)?;
    reach_toward(robot, &at, config, phase)?;
    tag.at = in_base(robot, &at)?;
    Ok(())
}

/// The action (asking the person when there are two) and its behaviour; `None`, failing the
/// phase, when the entry offers no action this robot can take.
fn choose_behavior<'e>(
    fetched: &'e Fetched,
    operator: &dyn Operator,
    phase: &mut PhaseReport,
) -> Result<Option<Chosen<'e>>, HalError> {
    let entry = &fetched.entry.entry;
    let Some(choice) = choose_action(entry, operator)? else {
        phase.fail(format!(
            "the entry offers {} actions; the interface chooses between one or two",
            entry.actions.len()
        ));
        return Ok(None);
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
        return Ok(None);
    }
    let Some((key, spec)) = entry.behavior_for(&action) else {
        phase.fail(format!("{action} names no behaviour in the entry"));
        return Ok(None);
    };
    Ok(Some(Chosen { action, key, spec }))
}

/// Runs the chosen behaviour, recording the fingers' forces; a behaviour that errs is an
/// [`Outcome::Error`] with the error as its detector, not the end of the task.
fn perform(
    acting: &Acting<'_, impl TaskRobot>,
    chosen: &Chosen<'_>,
    properties: &Properties,
    tag: Point3<f64>,
    phase: &mut PhaseReport,
) -> Performed {
    let Acting { robot, clock, config, .. } = *acting;
    let started = clock.now();
    let forces = ForceRecorder::new(robot, clock, started);
    let drop = DropGeometry { tag, sweep: config.drop_sweep, body: config.body, seed: 7 };
    let result =
        run_behavior(robot, &chosen.spec.params, properties, &chosen.action, &drop, forces);
    let finished = clock.now();
    let key = chosen.key;
    let (outcome, detector, measurements, forces) = match result {
        Ok(behavior) => {
            phase.note(format!("{key} ({}):", chosen.spec.kind()));
            for step in &behavior.steps {
                phase.note(format!("  {step}"));
            }
            (behavior.outcome, behavior.detector, behavior.measurements, behavior.forces)
        }
        Err(error) => {
            phase.note(format!("{key} failed: {error}"));
            let mut detector = Map::new();
            detector.insert("error".into(), error.to_string().into());
            (Outcome::Error, detector, Map::new(), Vec::new())
        }
    };
    Performed { started, finished, outcome, detector, measurements, forces }
}

/// The person's answer whether it worked, noted beside the detector's verdict.
fn ask_the_person(
    operator: &dyn Operator,
    outcome: Outcome,
    phase: &mut PhaseReport,
) -> Result<Option<bool>, HalError> {
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
    Ok(confirmed)
}

/// The trial as the registry stores it; the registry task it did, if any, goes in its
/// `measurements.task`.
fn trial_record(
    acting: &Acting<'_, impl TaskRobot>,
    tag: &FoundTag,
    chosen: Chosen<'_>,
    performed: Performed,
    confirmed: Option<bool>,
) -> Trial {
    let Performed { started, finished, outcome, detector, mut measurements, forces } = performed;
    if let Some(task) = acting.config.task {
        measurements.insert("task".into(), task.to_string().into());
    }
    Trial {
        id: Uuid::new_v4(),
        epc: tag.epc.clone(),
        robot: acting.registry.robot().clone(),
        action: chosen.action,
        behavior: chosen.key.to_owned(),
        started_at: started,
        finished_at: finished.max(started),
        outcome,
        confirmed,
        detector,
        forces,
        measurements,
        start_pose: acting.config.start_pose,
        purpose: acting.config.purpose,
        tag_color: tag.color,
        tag_size: tag.size,
        received_at: None,
        seq: None,
    }
}
