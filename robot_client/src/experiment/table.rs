//! Table I of the paper (§V): its twelve rows with the paper's figures, and ours beside them.

use serde_json::json;

use super::scoring::TableRow;
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

fn paper_name(device: DeviceKind) -> &'static str {
    match device {
        DeviceKind::LightSwitch => "Flip-type light switch",
        DeviceKind::AdaLightSwitch => "ADA rocker light switch",
        DeviceKind::Lamp => "Lamp",
        DeviceKind::TrashCan => "Trash can",
        DeviceKind::Drawer => "Cabinet drawer",
    }
}

/// The table beside the paper's figures.
pub fn render_table(rows: &[TableRow], randomized: bool) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "{:<26} {:<26} {:>9} {:>8}\n",
        "PPS-tagged object", "scenario", "ours", "paper"
    ));
    let (mut ours, mut trials, mut paper) = (0, 0, 0);
    for row in rows.iter().filter(|r| r.trials > 0) {
        let rate = 100.0 * f64::from(row.successes) / f64::from(row.trials);
        out.push_str(&format!(
            "{:<26} {:<26} {:>4}/{:<4} {:>4}/4   ({rate:.0}%)\n",
            paper_name(row.protocol.device),
            row.protocol.scenario,
            row.successes,
            row.trials,
            row.protocol.paper
        ));
        ours += row.successes;
        trials += row.trials;
        paper += row.protocol.paper;
    }
    let paper_total = if randomized { String::from("-") } else { format!("{paper}/48") };
    out.push_str(&format!("{:<53} {:>4}/{:<4} {:>6}\n", "all", ours, trials, paper_total));
    for row in rows {
        for miss in &row.misses {
            out.push_str(&format!("miss: {miss}\n"));
        }
    }
    out
}

/// The rows that ran, as one JSON document `{"rows": [...]}`.
pub fn rows_json(rows: &[TableRow]) -> serde_json::Value {
    json!({
        "rows": rows.iter().filter(|r| r.trials > 0).map(|r| json!({
            "device": r.protocol.device.type_name(),
            "scenario": r.protocol.scenario,
            "successes": r.successes,
            "trials": r.trials,
        })).collect::<Vec<_>>()
    })
}
