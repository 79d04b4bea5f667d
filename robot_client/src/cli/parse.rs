//! The simulator's devices and start directions as the command line spells them, for the
//! subcommands that set up a simulated room.

use crate::sim::{DeviceKind, StartDirection};

pub(super) fn parse_device(name: &str) -> Result<DeviceKind, String> {
    DeviceKind::parse(name).ok_or_else(|| {
        format!("`{name}` is not one of light-switch, ada-light-switch, lamp, drawer, trash-can")
    })
}

pub(super) fn parse_direction(name: &str) -> Result<StartDirection, String> {
    StartDirection::parse(name)
        .ok_or_else(|| format!("`{name}` is not one of far-left, left, front, right, far-right"))
}
