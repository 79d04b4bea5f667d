//! The simulated person: points where the script says, picks the action, and answers truthfully
//! whether it worked, because the person sees the room (the robot does not).

use nalgebra::Point3;

use crate::hal::{HalError, Operator, VerticalChoice};
use crate::sim::{DeviceKind, DeviceTruth, SimOperator, SimRobot};

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
pub(super) struct Person {
    pub(super) pointer: SimOperator,
    pub(super) robot: SimRobot,
    pub(super) device: DeviceKind,
    pub(super) action: String,
    pub(super) before: DeviceTruth,
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
