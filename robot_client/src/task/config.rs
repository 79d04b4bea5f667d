//! The task's settings: the paper's numbers, and this robot's body and sensors.

use pps_schema::{Purpose, StartPose};
use uuid::Uuid;

use crate::behaviors::RobotBody;
use crate::hal::TiltSweep;
use crate::navigation::ApproachParams;

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
