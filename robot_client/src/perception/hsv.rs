//! Colour segmentation by minimum and maximum HSV thresholds (paper §III-B, after [7]).
//!
//! Thresholds come from the tag entry's robot-specific `color_segmentation`; hue is in degrees
//! and wraps around 0, because the red of the tags straddles it (340..20).

use pps_schema::ColorSegmentation;

use super::mask::Mask;
use crate::hal::ColorImage;

/// Minimum and maximum hue (degrees), saturation and value (0..=1) of the tag's colour.
#[derive(Clone, Copy, PartialEq)]
pub struct HsvThresholds {
    /// Lower hue bound in 0..360; above `hue_to` when the range wraps through 0.
    hue_from: f32,
    hue_to: f32,
    every_hue: bool,
    saturation: [f32; 2],
    value: [f32; 2],
    /// For each brightest channel 0..=255, the least and greatest chroma (brightest minus
    /// dimmest channel) whose colour passes the value and saturation thresholds; `[1, 0]` when
    /// none does. Value depends on the brightest channel alone and saturation is chroma over
    /// it, so the two tests are one table lookup a pixel, most pixels failing there.
    chroma_bounds: [[u8; 2]; 256],
}

impl std::fmt::Debug for HsvThresholds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HsvThresholds")
            .field("hue_from", &self.hue_from)
            .field("hue_to", &self.hue_to)
            .field("every_hue", &self.every_hue)
            .field("saturation", &self.saturation)
            .field("value", &self.value)
            .finish_non_exhaustive()
    }
}

/// Why thresholds cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ThresholdError {
    #[error("hue, saturation and value thresholds must be finite numbers")]
    NotFinite,
    #[error("saturation and value are fractions 0..1 (got {0}); hue alone is in degrees")]
    NotAFraction(f64),
}

impl HsvThresholds {
    /// Thresholds from a tag entry, checked: saturation and value must be fractions.
    pub fn new(segmentation: &ColorSegmentation) -> Result<Self, ThresholdError> {
        let all = [segmentation.hue_deg, segmentation.saturation, segmentation.value].concat();
        if !all.iter().all(|v| v.is_finite()) {
            return Err(ThresholdError::NotFinite);
        }
        for v in segmentation.saturation.iter().chain(&segmentation.value) {
            if !(0.0..=1.0).contains(v) {
                return Err(ThresholdError::NotAFraction(*v));
            }
        }
        let mut thresholds = Self {
            hue_from: 0.0,
            hue_to: 0.0,
            every_hue: false,
            saturation: segmentation.saturation.map(|v| v as f32),
            value: segmentation.value.map(|v| v as f32),
            chroma_bounds: [[1, 0]; 256],
        }
        .with_hues(segmentation.hue_deg);
        for max in 0..=u8::MAX {
            // Passing is an interval of chroma: the test is `low ≤ chroma ≤ high` for bounds
            // that depend on `max` alone.
            let mut passing =
                (0..=max).filter(|&chroma| thresholds.passes_value_and_saturation(max, chroma));
            if let (Some(least), Some(greatest)) = (passing.clone().next(), passing.next_back()) {
                thresholds.chroma_bounds[usize::from(max)] = [least, greatest];
            }
        }
        Ok(thresholds)
    }

    /// These thresholds with their hues `hue_deg` (from, to, wrapping through 0 when from is
    /// above to), saturation and value kept.
    pub fn with_hues(self, [from, to]: [f64; 2]) -> Self {
        Self {
            hue_from: from.rem_euclid(360.0) as f32,
            hue_to: to.rem_euclid(360.0) as f32,
            every_hue: to - from >= 360.0,
            ..self
        }
    }

    /// Whether these thresholds take every hue `other` takes, and more.
    pub fn takes_more_hues_than(&self, other: &Self) -> bool {
        if self.every_hue {
            return !other.every_hue;
        }
        let (span, other_span) = (self.hue_span(), other.hue_span());
        !other.every_hue
            && span > other_span
            && (other.hue_from - self.hue_from).rem_euclid(360.0) + other_span <= span
    }

    /// How many degrees the hue range spans, counted from `hue_from` up to `hue_to`.
    fn hue_span(&self) -> f32 {
        (self.hue_to - self.hue_from).rem_euclid(360.0)
    }

    /// Whether a colour whose brightest channel is `max` and whose chroma is `chroma` passes
    /// the value and saturation thresholds: the rule the table of chroma bounds is made from.
    fn passes_value_and_saturation(&self, max: u8, chroma: u8) -> bool {
        let value = f32::from(max) * (1.0 / 255.0);
        if value < self.value[0] || value > self.value[1] {
            return false;
        }
        let (chroma, max_f) = (f32::from(chroma), f32::from(max));
        // Saturation = chroma / max; compared without dividing.
        max != 0 && chroma >= self.saturation[0] * max_f && chroma <= self.saturation[1] * max_f
    }

    /// Whether a hue in degrees (0..360) is inside the range, wrapping through 0 when the lower
    /// bound is above the upper one.
    pub fn contains_hue(&self, hue: f32) -> bool {
        if self.every_hue {
            true
        } else if self.hue_from <= self.hue_to {
            (self.hue_from..=self.hue_to).contains(&hue)
        } else {
            hue >= self.hue_from || hue <= self.hue_to
        }
    }

    /// How far a point of the chroma disc ([`chroma_point`]) lies from the hues and
    /// saturations the ranges admit, whatever its value: 0 inside them.
    pub fn chroma_distance(&self, [x, y]: [f32; 2]) -> f32 {
        let saturation = x.hypot(y);
        let hue = hue_of_chroma_point([x, y]);
        let [least, most] = self.saturation;
        if self.contains_hue(hue) {
            return (least - saturation).max(saturation - most).max(0.0);
        }
        // Outside the hues, the nearest admitted chroma lies on one of the two edges of the
        // admitted sector: the segment of saturations at its first or its last hue.
        let to_edge = |edge: f32| {
            let (sin, cos) = edge.to_radians().sin_cos();
            let along = (x * cos + y * sin).clamp(least, most);
            (x - along * cos).hypot(y - along * sin)
        };
        to_edge(self.hue_from).min(to_edge(self.hue_to))
    }

    /// Whether an 8-bit sRGB colour passes all three thresholds.
    #[inline]
    pub fn contains(&self, [r, g, b]: [u8; 3]) -> bool {
        let max = r.max(g).max(b);
        let chroma = max - r.min(g).min(b);
        let [least, greatest] = self.chroma_bounds[usize::from(max)];
        if chroma < least || chroma > greatest {
            return false;
        }
        self.contains_hue(hue_deg([r, g, b], max, f32::from(chroma)))
    }

    /// Word `i` of row `y` of the segmented image: bit `k` for pixel `64 i + k` passing.
    #[inline]
    pub(crate) fn word_of(&self, image: &ColorImage, i: usize, y: usize) -> u64 {
        let width = image.width as usize;
        let row = &image.rgb[y * width * 3..(y + 1) * width * 3];
        let chunk = &row[i * 64 * 3..((i + 1) * 64 * 3).min(row.len())];
        let mut bits = 0u64;
        for (k, px) in chunk.chunks_exact(3).enumerate() {
            if self.contains([px[0], px[1], px[2]]) {
                bits |= 1 << k;
            }
        }
        bits
    }
}

impl Default for HsvThresholds {
    fn default() -> Self {
        Self::new(&ColorSegmentation::default()).expect("the default thresholds are valid")
    }
}

/// Hue in degrees (0..360) of an sRGB colour with the given max channel and chroma.
fn hue_deg([r, g, b]: [u8; 3], max: u8, chroma: f32) -> f32 {
    if chroma == 0.0 {
        return 0.0;
    }
    let (rf, gf, bf) = (f32::from(r), f32::from(g), f32::from(b));
    let h = if max == r {
        (gf - bf) / chroma
    } else if max == g {
        (bf - rf) / chroma + 2.0
    } else {
        (rf - gf) / chroma + 4.0
    };
    (h * 60.0).rem_euclid(360.0)
}

/// Hue (degrees, 0..360), saturation and value (0..=1) of an 8-bit sRGB colour.
pub fn hsv_of([r, g, b]: [u8; 3]) -> [f32; 3] {
    let max = r.max(g).max(b);
    let chroma = f32::from(max - r.min(g).min(b));
    let hue = hue_deg([r, g, b], max, chroma);
    let saturation = if max == 0 { 0.0 } else { chroma / f32::from(max) };
    [hue, saturation, f32::from(max) / 255.0]
}

/// A colour as a point of the chroma disc: saturation as the radius, hue as the angle. Hue
/// alone wraps at 0° and means nothing for pale pixels; here near colours are near points.
pub fn chroma_point(rgb: [u8; 3]) -> [f32; 2] {
    let [hue, saturation, _] = hsv_of(rgb);
    polar(hue, saturation)
}

/// The hue of a point of the chroma disc ([`chroma_point`]), degrees in 0..360.
pub fn hue_of_chroma_point([x, y]: [f32; 2]) -> f32 {
    y.atan2(x).to_degrees().rem_euclid(360.0)
}

fn polar(hue_deg: f32, saturation: f32) -> [f32; 2] {
    let (sin, cos) = hue_deg.to_radians().sin_cos();
    [saturation * cos, saturation * sin]
}

/// The pixels of `image` whose colour passes `thresholds`: the paper's raw segmented image.
pub fn segment_color(image: &ColorImage, thresholds: &HsvThresholds) -> Mask {
    let (width, height) = (image.width as usize, image.height as usize);
    let mut mask = Mask::new(width, height);
    for y in 0..height {
        for (i, word) in mask.row_mut(y).iter_mut().enumerate() {
            *word = thresholds.word_of(image, i, y);
        }
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 8-bit sRGB of a colour (test data; perception itself never touches the simulator).
    fn hsv_to_rgb(h: f64, s: f64, v: f64) -> [u8; 3] {
        crate::sim::hsv_to_srgb(h as f32, s as f32, v as f32).map(|c| (c * 255.0).round() as u8)
    }

    #[test]
    fn red_hue_range_wraps_through_zero() {
        let red = HsvThresholds::default();
        for h in [340.5, 350.0, 359.9, 0.0, 5.0, 19.5] {
            assert!(red.contains(hsv_to_rgb(h, 0.9, 0.8)), "hue {h} is red");
        }
        for h in [25.0, 60.0, 120.0, 200.0, 330.0] {
            assert!(!red.contains(hsv_to_rgb(h, 0.9, 0.8)), "hue {h} is not red");
        }
        let green_to_blue =
            HsvThresholds::new(&ColorSegmentation { hue_deg: [20.0, 340.0], ..Default::default() })
                .unwrap();
        assert!(green_to_blue.contains(hsv_to_rgb(120.0, 0.9, 0.8)));
        assert!(!green_to_blue.contains(hsv_to_rgb(0.0, 0.9, 0.8)));
        let negative_start =
            HsvThresholds::new(&ColorSegmentation { hue_deg: [-20.0, 20.0], ..Default::default() })
                .unwrap();
        assert!(negative_start.contains(hsv_to_rgb(345.0, 0.9, 0.8)));
        let every =
            HsvThresholds::new(&ColorSegmentation { hue_deg: [0.0, 360.0], ..Default::default() })
                .unwrap();
        assert!(every.contains(hsv_to_rgb(200.0, 0.9, 0.8)));
    }

    #[test]
    fn saturation_and_value_bound_the_red() {
        let red = HsvThresholds::default();
        assert!(!red.contains(hsv_to_rgb(0.0, 0.3, 0.8)), "pink is too pale");
        assert!(!red.contains(hsv_to_rgb(0.0, 0.9, 0.1)), "too dark to trust");
        assert!(!red.contains([240, 235, 225]), "off-white wall");
        assert!(!red.contains([0, 0, 0]));
        // Reddish-brown wood sits just past the hue bound.
        assert!(!red.contains(hsv_to_rgb(24.0, 0.7, 0.5)));
    }

    #[test]
    fn the_chroma_table_is_the_value_and_saturation_rule() {
        let pale =
            ColorSegmentation { saturation: [0.05, 0.6], value: [0.3, 0.9], ..Default::default() };
        for thresholds in [HsvThresholds::default(), HsvThresholds::new(&pale).unwrap()] {
            for max in 0..=u8::MAX {
                for chroma in 0..=max {
                    let [least, greatest] = thresholds.chroma_bounds[usize::from(max)];
                    assert_eq!(
                        (least..=greatest).contains(&chroma),
                        thresholds.passes_value_and_saturation(max, chroma),
                        "max {max}, chroma {chroma}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_point_of_the_chroma_disc_lies_as_far_from_the_ranges_as_its_hue_and_saturation_say() {
        let t = HsvThresholds::default();
        let distance = |rgb| t.chroma_distance(chroma_point(rgb));
        assert_eq!(distance([200, 30, 20]), 0.0);
        // Just past 0° on the magenta side, wrapping through it.
        assert_eq!(distance([200, 20, 40]), 0.0);
        // The same red, paler: saturation 0.5, 0.1 under the default 0.6.
        assert!((distance([200, 110, 100]) - 0.1).abs() < 1e-3, "{}", distance([200, 110, 100]));
        // Orange-brown wood: hue 30° at saturation 0.78, 10° past the range's 20°.
        let wood = distance([180, 110, 40]);
        let expected = (140.0f32 / 180.0) * 10.0f32.to_radians().sin();
        assert!((wood - expected).abs() < 2e-3, "{wood} against {expected}");
        // A grey: as far as the range's least saturation.
        assert!((distance([120, 120, 120]) - 0.6).abs() < 1e-3);
    }

    #[test]
    fn rejects_fractions_out_of_range() {
        let opencv_style = ColorSegmentation {
            hue_deg: [0.0, 10.0],
            saturation: [157.0, 255.0],
            value: [34.0, 255.0],
        };
        assert_eq!(HsvThresholds::new(&opencv_style), Err(ThresholdError::NotAFraction(157.0)));
    }

    #[test]
    fn segments_pixel_by_pixel() {
        let mut image = ColorImage::new(130, 2);
        for x in [0usize, 63, 64, 129] {
            image.rgb[(130 + x) * 3..(130 + x) * 3 + 3].copy_from_slice(&[200, 20, 30]);
        }
        let mask = segment_color(&image, &HsvThresholds::default());
        assert_eq!(mask.count(), 4);
        assert!(mask.get(0, 1) && mask.get(63, 1) && mask.get(64, 1) && mask.get(129, 1));
    }
}
