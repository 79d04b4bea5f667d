//! The simulated person with the laser pointer: they point at a device's tag, and the robot's
//! 3D estimate of the spot is off by centimetres, mostly along the line of sight.

use std::sync::Mutex;

use nalgebra::{Point3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::noise::gaussian;
use super::robot::SimRobot;
use super::room::DeviceKind;
use crate::hal::{HalError, Operator, VerticalChoice};

/// How the person behaves in one scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OperatorScript {
    /// The device they point at; `None` when they point at nothing.
    pub target: Option<DeviceKind>,
    pub choice: VerticalChoice,
    /// Their answer to "did it work?".
    pub answer: Option<bool>,
    /// Standard deviation of the spot's 3D estimate along and across the line of sight, metres.
    pub depth_error: f64,
    pub lateral_error: f64,
}

impl Default for OperatorScript {
    fn default() -> Self {
        Self {
            target: None,
            choice: VerticalChoice::Up,
            answer: Some(true),
            depth_error: 0.03,
            lateral_error: 0.01,
        }
    }
}

/// The operator of a [`SimRobot`], seeing the world through it.
#[derive(Debug)]
pub struct SimOperator {
    robot: SimRobot,
    script: OperatorScript,
    rng: Mutex<ChaCha8Rng>,
}

impl SimOperator {
    pub fn new(robot: SimRobot, script: OperatorScript, seed: u64) -> Self {
        Self { robot, script, rng: Mutex::new(ChaCha8Rng::seed_from_u64(seed)) }
    }
}

impl Operator for SimOperator {
    fn pointed_target(&self) -> Result<Option<Point3<f64>>, HalError> {
        let Some(kind) = self.script.target else { return Ok(None) };
        let (world_from_base, eye) = {
            let s = self.robot.state();
            let world = s.body.world_from_base_3d();
            (world, world * Point3::from(s.geometry.camera.base_from_camera.translation.vector))
        };
        let spot = self.robot.state().room.device(kind).tag_center;
        let sight = (spot - eye).normalize();
        let across = sight.cross(&Vector3::z()).try_normalize(1e-9).unwrap_or(Vector3::x());
        let up = across.cross(&sight);
        let mut rng = self.rng.lock().unwrap_or_else(|p| p.into_inner());
        let error = sight * self.script.depth_error * gaussian(&mut *rng)
            + (across * gaussian(&mut *rng) + up * gaussian(&mut *rng)) * self.script.lateral_error;
        Ok(Some(world_from_base.inverse() * (spot + error)))
    }

    fn choose_action(&self) -> Result<VerticalChoice, HalError> {
        Ok(self.script.choice)
    }

    fn confirm_success(&self) -> Result<Option<bool>, HalError> {
        Ok(self.script.answer)
    }
}
