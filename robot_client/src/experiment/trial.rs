//! One simulated trial, set up as an experimenter would: the room, where the robot starts, the
//! devices' initial state and the injected failure. The robot's side is [`run_task`], which sees
//! only the hardware traits; the room's truth before and after is kept beside its report.

use pps_schema::StartPose;
use time::OffsetDateTime;

use super::person::{Person, achieved};
use super::real_reader::WithRealReader;
use crate::hal::{PlanarPose, RfidReader, VerticalChoice};
use crate::registry::RegistryClient;
use crate::sim::{
    BodyState, DeviceKind, DeviceTruth, OperatorScript, Room, RoomOptions, Scenario, SimBody,
    SimClock, SimOperator, SimRobot, start_pose_at_angle,
};
use crate::task::{TaskConfig, TaskReport, run_task, vertical_choice_for};

/// The failures of the paper's second set of trials.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    LampUnplugged,
    DrawerStuck,
    StickyObject,
}

/// One simulated trial as the experimenter sets it up.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedTrial {
    pub device: DeviceKind,
    pub action: String,
    pub scenario: Scenario,
    pub room: RoomOptions,
    /// From the tag's normal, radians, and distance from the tag, metres.
    pub start_angle: f64,
    pub start_distance: f64,
    pub seed: u64,
    /// The robot's simulated body, as its class in the registry says.
    pub body: SimBody,
}

impl SimulatedTrial {
    /// The device's usual starting state for `action`, with `fault` injected.
    pub fn new(device: DeviceKind, action: &str, fault: Option<Fault>) -> Self {
        let mut scenario = Scenario::office();
        match (device, action) {
            (DeviceKind::LightSwitch | DeviceKind::AdaLightSwitch, "on") => {
                scenario.ceiling_light_on = false
            }
            (DeviceKind::Lamp, "off") => scenario.lamp_on = true,
            (DeviceKind::Drawer, "close") => scenario.drawer_open = 0.3,
            (DeviceKind::TrashCan, _) => scenario.object_in_hand = true,
            _ => {}
        }
        match fault {
            Some(Fault::LampUnplugged) => scenario.lamp_unplugged = true,
            Some(Fault::DrawerStuck) => scenario.drawer_stuck = true,
            Some(Fault::StickyObject) => scenario.sticky_object = true,
            None => {}
        }
        Self {
            device,
            action: action.to_owned(),
            scenario,
            room: RoomOptions::default(),
            start_angle: 0.0,
            start_distance: 1.5,
            seed: 0,
            body: SimBody::ElE,
        }
    }
}

/// What happened, as the robot reported it and as the room truly is.
#[derive(Debug, Clone)]
pub struct SimulatedResult {
    pub report: TaskReport,
    pub before: DeviceTruth,
    pub after: DeviceTruth,
    /// Whether the room changed as the person wanted.
    pub achieved: bool,
    /// Every pose the base truly stood in, world frame, from where it started (the
    /// simulator's [`base_path`](crate::sim::SimState::base_path)).
    pub base_path: Vec<PlanarPose>,
    /// Where in `base_path` the base stood at the robot's last RFID read, if its reader is the
    /// simulator's.
    pub read_from: Option<usize>,
    /// Every state the body truly was in (the simulator's
    /// [`body_path`](crate::sim::SimState::body_path)), and where in it the body stood at the
    /// robot's last RFID read.
    pub body_path: Vec<BodyState>,
    pub body_read_from: Option<usize>,
}

/// Runs one task in a fresh simulated room against the registry.
pub async fn run_simulated(
    trial: &SimulatedTrial,
    registry: &RegistryClient,
    config: &TaskConfig,
) -> anyhow::Result<SimulatedResult> {
    run_simulated_reading(trial, registry, config, None).await
}

/// [`run_simulated`], its phase-3 RFID read from `rfid` (a real reader) when given.
pub async fn run_simulated_reading(
    trial: &SimulatedTrial,
    registry: &RegistryClient,
    config: &TaskConfig,
    rfid: Option<&dyn RfidReader>,
) -> anyhow::Result<SimulatedResult> {
    let room = Room::new(trial.room);
    let start =
        start_pose_at_angle(room.device(trial.device), trial.start_angle, trial.start_distance);
    let robot = SimRobot::of_class(room, start, trial.seed, trial.scenario, trial.body);
    // The person picks up or down as the interface's convention has it for the entry.
    let choice = match registry.effective_entry(&trial.device.epc()).await {
        Ok(fetched) => vertical_choice_for(&fetched.entry.entry, &trial.action),
        Err(_) => None,
    };
    let script = OperatorScript {
        target: Some(trial.device),
        choice: choice.unwrap_or(VerticalChoice::Up),
        ..OperatorScript::default()
    };
    let before = robot.truth();
    let person = Person {
        pointer: SimOperator::new(robot.clone(), script, trial.seed ^ 0x5EED),
        robot: robot.clone(),
        device: trial.device,
        action: trial.action.clone(),
        before,
    };
    let clock = SimClock::new(robot.clone(), OffsetDateTime::now_utc());
    let config = TaskConfig {
        start_pose: Some(StartPose {
            x: start.translation.x,
            y: start.translation.y,
            yaw: start.rotation.angle(),
        }),
        ..config.clone()
    };
    let report = match rfid {
        Some(reader) => {
            let robot = WithRealReader { robot: robot.clone(), reader };
            run_task(&robot, &person, registry, &clock, &config).await?
        }
        None => run_task(&robot, &person, registry, &clock, &config).await?,
    };
    let after = robot.truth();
    let (base_path, read_from, body_path, body_read_from) = {
        let state = robot.state();
        (state.base_path.clone(), state.read_from, state.body_path.clone(), state.body_read_from)
    };
    Ok(SimulatedResult {
        base_path,
        read_from,
        body_path,
        body_read_from,
        achieved: achieved(trial.device, &trial.action, &before, &after),
        report,
        before,
        after,
    })
}
