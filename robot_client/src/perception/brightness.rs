//! Whether a light went on or off (paper §IV-B.2.b): the mean intensity of where the light
//! source is expected, before the action minus after it.

/// What the brightness change says happened to the light.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightChange {
    TurnedOn,
    TurnedOff,
    Unchanged,
}

/// The measurements behind a [`LightChange`], kept for the trial record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BrightnessChange {
    /// Mean intensity before and after the action, 0..=255.
    pub before: f64,
    pub after: f64,
    /// `before - after`: positive when the scene got darker.
    pub difference: f64,
    pub change: LightChange,
}

/// Compares mean intensities: a difference larger than `threshold` in magnitude is a change,
/// darker (positive) meaning the light was turned off, brighter (negative) on.
pub fn brightness_change(before: f64, after: f64, threshold: f64) -> BrightnessChange {
    let difference = before - after;
    let change = if difference.abs() <= threshold {
        LightChange::Unchanged
    } else if difference > 0.0 {
        LightChange::TurnedOff
    } else {
        LightChange::TurnedOn
    };
    BrightnessChange { before, after, difference, change }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_gives_the_direction_and_magnitude_the_decision() {
        assert_eq!(brightness_change(120.0, 60.0, 10.0).change, LightChange::TurnedOff);
        assert_eq!(brightness_change(60.0, 120.0, 10.0).change, LightChange::TurnedOn);
        assert_eq!(brightness_change(60.0, 65.0, 10.0).change, LightChange::Unchanged);
        assert_eq!(brightness_change(65.0, 60.0, 10.0).change, LightChange::Unchanged);
        assert_eq!(brightness_change(70.0, 60.0, 10.0).difference, 10.0);
    }
}
