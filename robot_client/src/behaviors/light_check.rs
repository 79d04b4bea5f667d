//! The lighting behaviours' success detector (paper §IV-B.2.b): the mean intensity of a picture
//! toward the light source before the action, minus the one after; a magnitude above the
//! threshold is a change, and its sign says whether the light went on or off.

use super::{Evidence, WantedLight, milli};
use crate::perception::{LightChange, brightness_change};

/// Whether the light changed as `wanted`, recording what the decision rested on.
/// `threshold` is the entry's `brightness_threshold`, a fraction of the intensity range.
pub fn light_changed_as_wanted(
    before: f64,
    after: f64,
    threshold: f64,
    wanted: WantedLight,
    evidence: &mut Evidence,
) -> bool {
    let threshold = threshold * 255.0;
    let change = brightness_change(before, after, threshold);
    evidence.detector("change", "overall_brightness");
    evidence.detector("brightness_before", milli(before));
    evidence.detector("brightness_after", milli(after));
    evidence.detector("brightness_difference", milli(change.difference));
    evidence.detector("threshold", milli(threshold));
    evidence.detector("saw", name(change.change));
    evidence.step(format!("brightness {before:.1} -> {after:.1}: {}", name(change.change)));
    match wanted {
        WantedLight::On => change.change == LightChange::TurnedOn,
        WantedLight::Off => change.change == LightChange::TurnedOff,
        WantedLight::Changed => change.change != LightChange::Unchanged,
    }
}

fn name(change: LightChange) -> &'static str {
    match change {
        LightChange::TurnedOn => "turned_on",
        LightChange::TurnedOff => "turned_off",
        LightChange::Unchanged => "unchanged",
    }
}
