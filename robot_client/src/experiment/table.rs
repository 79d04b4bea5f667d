//! Table I of the paper (§V): its twelve rows with the paper's figures.

use super::trial::Fault;
use crate::sim::DeviceKind;

/// One row of Table I: a device, a scenario, and the paper's figure for it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Protocol {
    pub device: DeviceKind,
    /// The paper's name for the row.
    pub scenario: &'static str,
    pub action: &'static str,
    pub fault: Option<Fault>,
    /// The paper's successes out of 4.
    pub paper: u32,
}

/// Table I's rows, in the paper's order.
pub const TABLE_ONE: [Protocol; 12] = [
    Protocol {
        device: DeviceKind::LightSwitch,
        scenario: "switching on",
        action: "on",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::LightSwitch,
        scenario: "switching off",
        action: "off",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::AdaLightSwitch,
        scenario: "switching on",
        action: "on",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::AdaLightSwitch,
        scenario: "switching off",
        action: "off",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::Lamp,
        scenario: "switching on",
        action: "on",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::Lamp,
        scenario: "detect switching failure",
        action: "on",
        fault: Some(Fault::LampUnplugged),
        paper: 4,
    },
    Protocol {
        device: DeviceKind::TrashCan,
        scenario: "drop object into",
        action: "drop",
        fault: None,
        paper: 4,
    },
    Protocol {
        device: DeviceKind::TrashCan,
        scenario: "detect dropping failure",
        action: "drop",
        fault: Some(Fault::StickyObject),
        paper: 4,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "pull open",
        action: "open",
        fault: None,
        paper: 3,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "push closed",
        action: "close",
        fault: None,
        paper: 3,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "detect pulling failure",
        action: "open",
        fault: Some(Fault::DrawerStuck),
        paper: 2,
    },
    Protocol {
        device: DeviceKind::Drawer,
        scenario: "detect pushing failure",
        action: "close",
        fault: Some(Fault::DrawerStuck),
        paper: 3,
    },
];
