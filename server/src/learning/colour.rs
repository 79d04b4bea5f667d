//! Learning the tags' colour from confirmed reads (issue 34, DESIGN §10): each trial a robot
//! sends after its fingers read the tag's EPC carries the colour statistics of the pixels it
//! took for the tag (`tag_color`), which are known to be that tag. From the real-use trials of
//! one robot class the registry learns each tag's colour model, and the household's from all
//! of the class's tags, as it learns `pull_distance`: within bounds, with provenance `learned`.
//!
//! A model is the hue arc holding every look's 5th to 95th percentile, widened by how much the
//! looks' median hues differ from one another. Hue is what the material decides; saturation and
//! value follow the light and the angle (a tag seen at 68° returns less of the flash, and
//! paler), so a few looks do not bound them: their floors are learned the same way but only
//! ever lowered below the factory's, and above they stay open.
//! Runs inside the transaction that records the trials, like the rest of learning; the looks and
//! the models are kept by `store::learned_colours`.

use pps_schema::{ColorSegmentation, Epc, LearnedColor, TagColor};
use serde_json::Value;
use sqlx::AnyConnection;

use crate::store::learned_colours;

/// Looks a model is learned from (the most recent ones), like the other learned values.
const LEARNING_WINDOW: i64 = 100;

/// Fewest looks a model rests on: with fewer, how much looks differ is not measured at all.
pub const MIN_LOOKS: usize = 3;

/// The widest hue arc a learned model may have, degrees: a wider one is no longer one colour
/// (half the circle reaches from red to cyan).
const MAX_HUE_ARC_DEG: f64 = 180.0;

/// Whether a trial carries what colour learning learns from.
pub fn teaches(trial: &Value) -> bool {
    trial.get("tag_color").is_some_and(Value::is_object)
}

/// What changed: the tag's own model, the household's.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct ColourChange {
    pub tag: bool,
    pub household: bool,
}

/// Learns the colour of `epc` and of its household for `robot_class` anew.
pub async fn update(
    conn: &mut AnyConnection,
    epc: &Epc,
    robot_class: Option<&str>,
) -> sqlx::Result<ColourChange> {
    let own = learned_colours::looks(conn, Some(epc), robot_class, LEARNING_WINDOW).await?;
    let tag = learned_colours::store(conn, epc.as_hex(), robot_class, learn(&own)).await?;
    let all = learned_colours::looks(conn, None, robot_class, LEARNING_WINDOW).await?;
    let household = learned_colours::store(conn, "", robot_class, learn(&all)).await?;
    Ok(ColourChange { tag, household })
}

/// The model `looks` teach, `None` when they are too few or it would be out of bounds.
pub fn learn(looks: &[TagColor]) -> Option<LearnedColor> {
    if looks.len() < MIN_LOOKS {
        return None;
    }
    // Hues as offsets from the looks' mean direction, so an arc through 0° stays one arc.
    let (sin, cos) = looks.iter().fold((0.0f64, 0.0f64), |(s, c), look| {
        let (ls, lc) = look.hue_deg[1].to_radians().sin_cos();
        (s + ls, c + lc)
    });
    let middle = sin.atan2(cos).to_degrees();
    let offset = |hue: f64| (hue - middle + 180.0).rem_euclid(360.0) - 180.0;
    let medians: Vec<f64> = looks.iter().map(|l| offset(l.hue_deg[1])).collect();
    let widen = spread(&medians);
    let low = looks.iter().map(|l| offset(l.hue_deg[0])).fold(f64::INFINITY, f64::min) - widen;
    let high = looks.iter().map(|l| offset(l.hue_deg[2])).fold(f64::NEG_INFINITY, f64::max) + widen;
    let factory = ColorSegmentation::default();
    let floor = |pick: fn(&TagColor) -> [f64; 3], factory: f64| {
        let lows = looks.iter().map(|l| pick(l)[0]).fold(f64::INFINITY, f64::min);
        let medians: Vec<f64> = looks.iter().map(|l| pick(l)[1]).collect();
        round((lows - spread(&medians)).clamp(0.0, 1.0).min(factory))
    };
    let model = LearnedColor {
        segmentation: ColorSegmentation {
            hue_deg: [
                round((middle + low).rem_euclid(360.0)),
                round((middle + high).rem_euclid(360.0)),
            ],
            saturation: [floor(|l| l.saturation, factory.saturation[0]), 1.0],
            value: [floor(|l| l.value, factory.value[0]), 1.0],
        },
        trials: looks.len() as u64,
    };
    within_bounds(&model, high - low).then_some(model)
}

/// The standard deviation of `values` about their mean (0 for one value).
fn spread(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt()
}

fn round(value: f64) -> f64 {
    (value * 1000.0).round() / 1000.0
}

/// Whether a model is one colour a tag can have: within the entry schema's bounds for a
/// `color_segmentation` (hues 0 to 360, fractions 0 to 1, none above its maximum), and a hue arc
/// shorter than half the circle.
fn within_bounds(model: &LearnedColor, arc_deg: f64) -> bool {
    let ColorSegmentation { hue_deg, saturation, value } = model.segmentation;
    let fraction = |[low, high]: [f64; 2]| (0.0..=1.0).contains(&low) && low <= high && high <= 1.0;
    let fits = arc_deg.is_finite()
        && arc_deg < MAX_HUE_ARC_DEG
        && hue_deg.iter().all(|h| (0.0..=360.0).contains(h))
        && fraction(saturation)
        && fraction(value);
    if !fits {
        tracing::warn!(?model, arc_deg, "a learned colour is outside its bounds; not learned");
    }
    fits
}

#[cfg(test)]
mod tests {
    use super::*;

    fn look(hue: [f64; 3], saturation: [f64; 3]) -> TagColor {
        TagColor { pixels: 400, hue_deg: hue, saturation, value: [0.3, 0.5, 0.7], light_level: 0.4 }
    }

    #[test]
    fn looks_through_red_make_one_arc_within_bounds() {
        let looks = [
            look([354.0, 1.0, 7.0], [0.80, 0.88, 0.95]),
            look([356.0, 2.0, 8.0], [0.78, 0.87, 0.95]),
            look([352.0, 0.0, 6.0], [0.82, 0.9, 0.96]),
        ];
        assert_eq!(learn(&looks[..2]), None, "two looks are too few");
        let model = learn(&looks).unwrap();
        let [from, to] = model.segmentation.hue_deg;
        assert!(from > 350.0 && from < 352.0, "{from}");
        assert!(to > 8.0 && to < 10.0, "{to}");
        // Never above the factory's floors: the light, not the tag, decides how pale it looks.
        assert_eq!(model.segmentation.saturation[0], 0.6);
        assert_eq!(model.segmentation.value[0], 0.15);
        assert_eq!(model.trials, 3);
        // Plywood's hue, 14–24°, lies outside.
        assert!(to < 14.0);
        let scattered = [
            look([10.0, 30.0, 60.0], [0.5, 0.6, 0.7]),
            look([100.0, 150.0, 200.0], [0.5, 0.6, 0.7]),
            look([200.0, 250.0, 300.0], [0.5, 0.6, 0.7]),
        ];
        assert_eq!(learn(&scattered), None, "no one colour");
    }
}
