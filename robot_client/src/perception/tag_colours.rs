//! The colour phase 2 looks for. The robot has not read the tag's RFID yet, so it cannot use that
//! tag's entry: it looks for any colour its camera sees the registry's tags in, the smallest
//! range holding every entry's `color_segmentation` as the registry merged it for this robot
//! (its class's and its own overrides applied). Then a camera that sees red as orange finds the
//! tags by the entries alone, with no code that knows which camera it is.

use pps_schema::ColorSegmentation;

/// The smallest thresholds holding every one of `colours`: the shortest arc of hue covering all
/// their hue arcs, and the widest saturation and value. The paper's red when there are none.
pub fn covering_colour(colours: impl IntoIterator<Item = ColorSegmentation>) -> ColorSegmentation {
    let mut colours = colours.into_iter().peekable();
    if colours.peek().is_none() {
        return ColorSegmentation::default();
    }
    let mut arcs: Vec<(f64, f64)> = Vec::new();
    let mut saturation = [f64::INFINITY, f64::NEG_INFINITY];
    let mut value = [f64::INFINITY, f64::NEG_INFINITY];
    for colour in colours {
        let [from, to] = colour.hue_deg;
        let length = if to - from >= 360.0 { 360.0 } else { (to - from).rem_euclid(360.0) };
        arcs.push((from.rem_euclid(360.0), length));
        saturation =
            [saturation[0].min(colour.saturation[0]), saturation[1].max(colour.saturation[1])];
        value = [value[0].min(colour.value[0]), value[1].max(colour.value[1])];
    }
    // The covering arc starts where one of the arcs starts; from each start, it must reach the
    // far end of every arc.
    let reach = |start: f64| {
        arcs.iter()
            .map(|&(from, length)| (from - start).rem_euclid(360.0) + length)
            .fold(0.0, f64::max)
    };
    let (start, length) = arcs
        .iter()
        .map(|&(from, _)| (from, reach(from)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("at least one colour");
    let hue_deg = if length >= 360.0 { [0.0, 360.0] } else { [start, start + length] };
    ColorSegmentation { hue_deg, saturation, value }
}

/// Hue bounds as a person reads them, both in 0..360 (`340..20°` wraps through red).
pub fn describe_colour(colour: &ColorSegmentation) -> String {
    let [from, to] = colour.hue_deg;
    let hue = if to - from >= 360.0 {
        String::from("any hue")
    } else {
        format!("hue {:.0}..{:.0}°", from.rem_euclid(360.0), to.rem_euclid(360.0))
    };
    format!(
        "{hue}, saturation {:.2}..{:.2}, value {:.2}..{:.2}",
        colour.saturation[0], colour.saturation[1], colour.value[0], colour.value[1]
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn colour(hue_deg: [f64; 2], low_saturation: f64) -> ColorSegmentation {
        ColorSegmentation { hue_deg, saturation: [low_saturation, 1.0], value: [0.15, 1.0] }
    }

    #[test]
    fn arcs_through_red_join_the_short_way_round() {
        let joined = covering_colour([colour([340.0, 20.0], 0.6), colour([10.0, 33.0], 0.45)]);
        assert_eq!(joined.hue_deg, [340.0, 393.0]);
        assert_eq!(joined.saturation, [0.45, 1.0]);
        assert_eq!(
            describe_colour(&joined),
            "hue 340..33°, saturation 0.45..1.00, value 0.15..1.00"
        );
    }

    #[test]
    fn apart_arcs_are_covered_across_the_smaller_gap() {
        let joined = covering_colour([colour([340.0, 20.0], 0.6), colour([100.0, 120.0], 0.6)]);
        assert_eq!(joined.hue_deg, [340.0, 480.0], "340..120 spans 140°, 100..20 would be 280°");
    }

    #[test]
    fn one_colour_is_itself_and_none_is_the_papers_red() {
        let one = colour([10.0, 33.0], 0.45);
        assert_eq!(covering_colour([one]), one);
        assert_eq!(covering_colour([]), ColorSegmentation::default());
        let all = covering_colour([colour([0.0, 360.0], 0.5), one]);
        assert_eq!(all.hue_deg, [0.0, 360.0]);
        assert_eq!(describe_colour(&all), "any hue, saturation 0.45..1.00, value 0.15..1.00");
    }
}
