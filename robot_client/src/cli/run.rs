//! `pps-robot run`: one task in the simulator against a registry, printed phase by phase.
//!
//! The simulated world here is set up as an experimenter would: the room, where the robot
//! starts, the devices' initial state and the injected failure, and a person who points, picks
//! the action and answers truthfully whether it worked (the person sees the room; the robot
//! does not). The robot's side is [`run_task`], which sees only the hardware traits.

use clap::Args;
use nalgebra::Point3;
use pps_schema::StartPose;
use time::OffsetDateTime;

use super::real_rfid::WithRealReader;
use super::registry_args::RegistryArgs;
use super::rfid::{ReadSettings, ReaderChoice, open_reader};
use crate::hal::{HalError, Operator, RfidReader, VerticalChoice};
use crate::registry::{RegistryClient, RegistryError};
use crate::sim::{
    DeviceKind, DeviceTruth, OperatorScript, Room, RoomOptions, Scenario, SimBody, SimClock,
    SimOperator, SimRobot, StartDirection, start_pose_at_angle,
};
use crate::task::{TaskConfig, TaskReport, run_task, vertical_choice_for};

#[derive(Debug, Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub registry: RegistryArgs,
    /// light-switch, ada-light-switch, lamp, drawer or trash-can.
    #[arg(long, value_parser = parse_device)]
    pub device: DeviceKind,
    /// The action the person wants, as the entry names it (on, off, open, close, drop).
    #[arg(long)]
    pub action: String,
    /// Seed of the simulated world's noise (and, with --randomized, of the trials drawn).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Where the robot starts, 1.5 m from the tag: far-left, left, front, right or far-right.
    #[arg(long = "from", default_value = "front", value_parser = parse_direction)]
    pub from: StartDirection,
    /// A failure to inject: lamp-unplugged, drawer-stuck or sticky-object.
    #[arg(long, value_parser = parse_fault)]
    pub fault: Option<Fault>,
    /// The simulated room: paper (the paper's lab) or home (red things beside the tags, the
    /// switches' tags 30 cm apart, lacquered fronts, evening light).
    #[arg(long, default_value = "paper", value_parser = RoomOptions::named)]
    pub room: RoomOptions,
    /// Phase 3 reads a real LLRP reader, HOST[:PORT], instead of the simulated fingers.
    #[arg(long, conflicts_with = "rfid_m5e")]
    pub rfid_llrp: Option<String>,
    /// Phase 3 reads a real ThingMagic M5e on this serial device.
    #[arg(long)]
    pub rfid_m5e: Option<String>,
    #[command(flatten)]
    pub rfid_read: ReadSettings,
}

/// The failures of the paper's second set of trials.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    LampUnplugged,
    DrawerStuck,
    StickyObject,
}

fn parse_fault(name: &str) -> Result<Fault, String> {
    match name {
        "lamp-unplugged" => Ok(Fault::LampUnplugged),
        "drawer-stuck" => Ok(Fault::DrawerStuck),
        "sticky-object" => Ok(Fault::StickyObject),
        _ => Err(format!("`{name}` is not one of lamp-unplugged, drawer-stuck, sticky-object")),
    }
}

pub(crate) fn parse_device(name: &str) -> Result<DeviceKind, String> {
    DeviceKind::parse(name).ok_or_else(|| {
        format!("`{name}` is not one of light-switch, ada-light-switch, lamp, drawer, trash-can")
    })
}

fn parse_direction(name: &str) -> Result<StartDirection, String> {
    StartDirection::parse(name)
        .ok_or_else(|| format!("`{name}` is not one of far-left, left, front, right, far-right"))
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
}

/// Whether the room changed as `action` on `device` wants.
pub fn achieved(
    device: DeviceKind,
    action: &str,
    before: &DeviceTruth,
    after: &DeviceTruth,
) -> bool {
    match (device, action) {
        (DeviceKind::LightSwitch | DeviceKind::AdaLightSwitch, "on") => after.ceiling_light_on,
        (DeviceKind::LightSwitch | DeviceKind::AdaLightSwitch, "off") => !after.ceiling_light_on,
        (DeviceKind::Lamp, "on") => after.lamp_on,
        (DeviceKind::Lamp, "off") => !after.lamp_on,
        (DeviceKind::Drawer, "open") => after.drawer_open >= before.drawer_open + 0.15,
        (DeviceKind::Drawer, "close") => after.drawer_open <= before.drawer_open - 0.15,
        (DeviceKind::TrashCan, _) => after.object_in_trash && !after.object_in_hand,
        _ => false,
    }
}

/// The person: points where the script says, and judges success by looking at the room.
#[derive(Debug)]
struct Person {
    pointer: SimOperator,
    robot: SimRobot,
    device: DeviceKind,
    action: String,
    before: DeviceTruth,
}

impl Operator for Person {
    fn pointed_target(&self) -> Result<Option<Point3<f64>>, HalError> {
        self.pointer.pointed_target()
    }

    fn choose_action(&self) -> Result<VerticalChoice, HalError> {
        self.pointer.choose_action()
    }

    fn confirm_success(&self) -> Result<Option<bool>, HalError> {
        Ok(Some(achieved(self.device, &self.action, &self.before, &self.robot.truth())))
    }
}

/// What the robot does when it starts: learns its class from the registry, so the simulator
/// builds that class's body, and reads the registry's tags into its cache. Without the registry
/// it goes on with the record and the entries it kept from the last time.
pub async fn start_up(registry: &RegistryClient) -> anyhow::Result<SimBody> {
    let record = match registry.robot_record().await {
        Ok(record) => record,
        Err(error @ RegistryError::Unreachable(_)) => anyhow::bail!(
            "{error}; this robot has never reached it, so it knows neither its class nor any tag"
        ),
        Err(error) if error.status() == Some(404) => anyhow::bail!(
            "robot {0} is not registered: an admin registers it, with its class, by \
             PUT /api/v1/robots/{0}",
            registry.robot()
        ),
        Err(error) => return Err(error.into()),
    };
    let known = SimBody::ALL.map(SimBody::class).join(" or ");
    let Some(class) = record.class.as_ref().map(|c| c.as_str()) else {
        anyhow::bail!(
            "robot {0} has no class yet: an admin sets one ({known}) by PUT /api/v1/robots/{0}",
            registry.robot()
        );
    };
    let Some(body) = SimBody::for_class(class) else {
        anyhow::bail!(
            "robot {} has class `{class}`; the simulator builds robots of class {known}",
            registry.robot()
        );
    };
    match registry.sync_entries().await {
        Ok(_) => {}
        Err(error @ RegistryError::Unreachable(_)) => {
            tracing::warn!(
                "{error}; going on with the {} entries kept",
                registry.known_entries().len()
            )
        }
        Err(error) => return Err(error.into()),
    }
    Ok(body)
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
    Ok(SimulatedResult {
        achieved: achieved(trial.device, &trial.action, &before, &after),
        report,
        before,
        after,
    })
}

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let registry = args.registry.connect()?;
    let choice = match (&args.rfid_llrp, &args.rfid_m5e) {
        (Some(address), _) => Some(ReaderChoice::Llrp(address.clone())),
        (None, Some(device)) => Some(ReaderChoice::M5e(device.clone())),
        (None, None) => None,
    };
    // Connected before the task starts, so an unreachable reader stops it at once.
    let reader = choice.map(|c| open_reader(&c, &args.rfid_read)).transpose()?;
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build()?;
    let result = runtime.block_on(async {
        let trial = SimulatedTrial {
            start_angle: args.from.angle(),
            seed: args.seed,
            room: args.room,
            body: start_up(&registry).await?,
            ..SimulatedTrial::new(args.device, &args.action, args.fault)
        };
        run_simulated_reading(&trial, &registry, &TaskConfig::default(), reader.as_deref()).await
    })?;
    tracing::info!("state directory: {}", args.registry.state_dir().display());
    print!("{}", result.report);
    Ok(())
}
