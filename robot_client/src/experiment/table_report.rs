//! Table I as the `trials` command prints it: our successes beside the paper's figures, as
//! text or as one JSON document.

use serde_json::json;

use super::scoring::TableRow;
use crate::sim::DeviceKind;

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
