//! Whether a red part can be a tag of the home (issue 34): no part reaching further from its
//! middle than the largest tag does, and, where the home's tags' sizes are known, no part wider
//! where the camera looks at it than the widest tag's narrower side, nor longer than the
//! longest tag's diagonal.
//!
//! The reach alone lets in a red thing about as large as the tag but of another shape: a
//! fabric 13 × 10 cm hanging beside a lamp's 13 × 3 cm foam tube reaches no further from its
//! middle than the tube, and was taken for it. Its width tells them apart. A flat rectangle
//! seen from anywhere, or a tube from anywhere, is never wider, in the plane square to the line
//! of sight, than its narrower side: the picture shrinks a rectangle's sides and keeps a tube's
//! diameter. Measured in that plane, the width owes nothing to the depth noise, which moves
//! points along their rays; it owes the camera's pixels (a strip covers one pixel more than its
//! width fills, and the colour split reads the mean of the pixels one around each point's own),
//! so a tag may be wider than registered by [`PIXELS_OF_SLACK`] pixels at its distance.
//!
//! The width lets in a red thing narrow where the camera looks at it: the face of a red box
//! seen nearly edge on beside a flip switch's 4 × 3 cm tube, a strip 3 cm wide and 7–10 cm long
//! that reaches no further from its middle than the tube and its fragments may. No tag, seen
//! from anywhere, is longer in any direction than its diagonal; the strip is.
//!
//! On the corpus's RGB-D scenes with sizes registered (500, red things touching the tags), no
//! part that was the tag itself was more than 1.7 pixels wider than registered; of the red
//! things taken in the tag's place that were wider than it, all but one were 6 pixels wider
//! and more (`FINDINGS.md`).

use std::fmt;

use nalgebra::{Point3, Vector3};

use super::occupancy::Component;
use super::tag_extent::trimmed_span;
use super::tag_search_params::TagSearchParams;
use crate::hal::CameraCalibration;

/// How many of the camera's pixels a tag may seem wider than it is: one for the pixel a strip's
/// edge half covers, and one each side for the pixels the colour split's mean reads around a
/// point's own.
const PIXELS_OF_SLACK: f64 = 3.0;

/// Share of a part's points left off each end of its width: stray points at its edges.
const TRIM: f64 = 0.02;

/// Most points a width is measured on; a larger part is sampled evenly.
const MOST_POINTS: usize = 512;

/// Directions in which a width is first measured, across half a turn from the direction of
/// least scatter; the narrowest is then refined to a degree.
const COARSE_TURNS: usize = 12;

/// The largest part a tag of the home can be, as the camera sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TagBound {
    /// How far the largest tag reaches from its middle, metres.
    reach: f64,
    /// The widest tag's narrower side, metres, when the home's tags' sizes are known.
    widest: Option<f64>,
    /// The longest tag's diagonal, metres, when the home's tags' sizes are known.
    longest: Option<f64>,
    /// The camera's centre, base frame.
    eye: Point3<f64>,
    /// One pixel's width at one metre, metres.
    pixel_at_one_metre: f64,
}

/// Why a part is no tag of the home.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum TooLarge {
    /// It reaches further from its middle than any tag: both distances across, metres.
    Across { across: f64, at_most: f64 },
    /// It is wider, where the camera looks at it, than any tag: its width, the widest tag's
    /// narrower side and that with the camera's pixels there, metres.
    Wide { width: f64, widest: f64, with_pixels: f64 },
    /// It is longer, where the camera looks at it, than any tag's diagonal: its length, the
    /// longest tag's diagonal and that with the camera's pixels there, metres.
    Long { length: f64, longest: f64, with_pixels: f64 },
}

impl TagBound {
    pub(super) fn new(params: &TagSearchParams, calibration: &CameraCalibration) -> Self {
        let k = &calibration.intrinsics;
        Self {
            reach: params.max_tag_radius,
            widest: params.widest_tag_half_width.map(|half| 2.0 * half),
            longest: params.home_tags.iter().map(|s| 2.0 * s.reach()).reduce(f64::max),
            eye: Point3::from(calibration.base_from_camera.translation.vector),
            pixel_at_one_metre: 1.0 / k.fx.min(k.fy),
        }
    }

    /// Whether `part` may be a tag of the home.
    pub(super) fn holds(&self, part: &Component) -> bool {
        self.too_large(part).is_none()
    }

    /// Why `part` cannot be a tag of the home; `None` when it may be one.
    pub(super) fn too_large(&self, part: &Component) -> Option<TooLarge> {
        if part.radius > self.reach {
            return Some(TooLarge::Across { across: 2.0 * part.radius, at_most: 2.0 * self.reach });
        }
        let (widest, longest) = (self.widest?, self.longest?);
        let distance = (part.centroid - self.eye).norm();
        let slack = PIXELS_OF_SLACK * self.pixel_at_one_metre * distance;
        let seen = SeenAcross::new(&part.members, &part.centroid, &self.eye)?;
        if let Some(width) = seen.narrowest_width_beyond(widest + slack) {
            return Some(TooLarge::Wide { width, widest, with_pixels: widest + slack });
        }
        let length = seen.length();
        (length > longest + slack).then_some(TooLarge::Long {
            length,
            longest,
            with_pixels: longest + slack,
        })
    }
}

impl fmt::Display for TooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Across { across, at_most } => write!(
                f,
                "{:.0} cm across, larger than any tag ({:.0} cm at most)",
                across * 100.0,
                at_most * 100.0
            ),
            Self::Wide { width, widest, with_pixels } => write!(
                f,
                "{:.1} cm wide as the camera sees it, wider than any tag ({:.1} cm at most, \
                 {:.1} cm with the camera's pixels there)",
                width * 100.0,
                widest * 100.0,
                with_pixels * 100.0
            ),
            Self::Long { length, longest, with_pixels } => write!(
                f,
                "{:.1} cm long as the camera sees it, longer than any tag's diagonal ({:.1} cm \
                 at most, {:.1} cm with the camera's pixels there)",
                length * 100.0,
                longest * 100.0,
                with_pixels * 100.0
            ),
        }
    }
}

/// A part's points in the plane square to the line of sight to its middle, a sample of them
/// for a large part.
struct SeenAcross {
    flat: Vec<[f64; 2]>,
    /// The angle from level of the points' axis of least scatter.
    least_scatter: f64,
}

impl SeenAcross {
    /// `points` seen from `eye`, about their centre `centre`; `None` for fewer than three.
    fn new(points: &[Point3<f32>], centre: &Point3<f64>, eye: &Point3<f64>) -> Option<Self> {
        if points.len() < 3 {
            return None;
        }
        let sight = (centre - eye).try_normalize(1e-9)?;
        let level = sight.cross(&Vector3::z()).try_normalize(1e-6).unwrap_or(Vector3::x());
        let upright = sight.cross(&level);
        let step = points.len().div_ceil(MOST_POINTS);
        let flat: Vec<[f64; 2]> = points
            .iter()
            .step_by(step)
            .map(|p| {
                let d = p.cast::<f64>() - centre;
                [d.dot(&level), d.dot(&upright)]
            })
            .collect();
        let least_scatter = direction_of_least_scatter(&flat);
        Some(Self { flat, least_scatter })
    }

    /// The width, 2nd to 98th percentile, measured along the direction `angle` from level.
    fn width_at(&self, angle: f64) -> f64 {
        let (sin, cos) = angle.sin_cos();
        trimmed_span(self.flat.iter().map(|[x, y]| x * cos + y * sin).collect(), TRIM)
    }

    /// The narrowest width, when it is more than `limit`; `None` as soon as some direction is
    /// no wider. The direction of least scatter is tried first, and is the narrowest of a
    /// rectangle or a tube: most parts are done with it.
    fn narrowest_width_beyond(&self, limit: f64) -> Option<f64> {
        let least_scatter = self.least_scatter;
        let coarse = std::f64::consts::PI / COARSE_TURNS as f64;
        let mut narrowest = (f64::INFINITY, least_scatter);
        for angle in (0..COARSE_TURNS).map(|i| least_scatter + i as f64 * coarse) {
            let width = self.width_at(angle);
            if width <= limit {
                return None;
            }
            if width < narrowest.0 {
                narrowest = (width, angle);
            }
        }
        // Within half a coarse turn of the narrowest, by degrees.
        let degree = 1f64.to_radians();
        let fine = (coarse / 2.0 / degree).ceil() as i32;
        let width = (-fine..=fine)
            .map(|i| self.width_at(narrowest.1 + f64::from(i) * degree))
            .fold(narrowest.0, f64::min);
        (width > limit).then_some(width)
    }

    /// The length, 2nd to 98th percentile, along the points' axis of most scatter: never more
    /// than the part's extent in its longest direction, which for a tag seen from anywhere is
    /// at most its diagonal.
    fn length(&self) -> f64 {
        self.width_at(self.least_scatter + std::f64::consts::FRAC_PI_2)
    }
}

/// The angle from level of the axis of least scatter of points `flat`.
fn direction_of_least_scatter(flat: &[[f64; 2]]) -> f64 {
    let n = flat.len() as f64;
    let [mx, my] = flat.iter().fold([0.0, 0.0], |[a, b], [x, y]| [a + x, b + y]);
    let (mx, my) = (mx / n, my / n);
    let [xx, yy, xy] = flat.iter().fold([0.0; 3], |[a, b, c], [x, y]| {
        let (dx, dy) = (x - mx, y - my);
        [a + dx * dx, b + dy * dy, c + dx * dy]
    });
    // The axis of most scatter is at half the angle of (xx - yy, 2 xy); least, square to it.
    0.5 * (2.0 * xy).atan2(xx - yy) + std::f64::consts::FRAC_PI_2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::head_camera;
    use nalgebra::{Rotation3, Translation3};
    use pps_schema::TagSize;

    /// The simulator's head camera at 320 × 240: a pixel 4 mm wide at 1 m.
    fn camera() -> CameraCalibration {
        head_camera(0.25)
    }

    /// The points of a `width` × `height` rectangle 2 mm apart, `range` metres along the
    /// camera's axis, facing it, then leaning `lean` about its upright and turned `turn` in its
    /// own plane.
    fn rectangle(width: f64, height: f64, turn: f64, lean: f64, range: f64) -> Component {
        let eye = camera().base_from_camera;
        let sight = eye.rotation * Vector3::z();
        let centre = eye.translation.vector + sight * range;
        let facing = Rotation3::rotation_between(&Vector3::x(), &-sight).expect("not opposite");
        let pose = Translation3::from(centre)
            * facing
            * Rotation3::from_axis_angle(&Vector3::z_axis(), lean.to_radians())
            * Rotation3::from_axis_angle(&Vector3::x_axis(), turn.to_radians());
        let (nw, nh) = ((width / 0.002) as i32, (height / 0.002) as i32);
        let members: Vec<Point3<f32>> = (0..=nw)
            .flat_map(|i| (0..=nh).map(move |j| (i, j)))
            .map(|(i, j)| {
                let local = Point3::new(
                    0.0,
                    f64::from(i) * 0.002 - width / 2.0,
                    f64::from(j) * 0.002 - height / 2.0,
                );
                (pose * local).cast()
            })
            .collect();
        Component {
            centroid: Point3::from(centre),
            points: members.len(),
            voxels: members.len() / 25,
            distance_to_target: 0.0,
            radius: (width.hypot(height)) / 2.0,
            members,
        }
    }

    fn tube_home() -> TagSearchParams {
        TagSearchParams::default().for_home_tags([TagSize { width: 0.13, height: 0.03 }])
    }

    #[test]
    fn a_tag_turned_or_leaning_is_never_wider_than_its_narrower_side() {
        let bound = TagBound::new(&tube_home(), &camera());
        for turn in [0.0, 20.0, 45.0, 90.0, 133.0] {
            for lean in [0.0, 40.0, 70.0] {
                let tube = rectangle(0.13, 0.03, turn, lean, 1.5);
                assert_eq!(bound.too_large(&tube), None, "turned {turn}°, leaning {lean}°");
            }
        }
    }

    #[test]
    fn a_red_thing_as_far_reaching_as_the_tag_but_wider_is_no_tag() {
        let bound = TagBound::new(&tube_home(), &camera());
        // A 12 × 8 cm fabric reaches 7.2 cm from its middle, no further than the tube's 6.6 cm
        // and its fragment gap.
        let fabric = rectangle(0.12, 0.08, 30.0, 20.0, 1.5);
        assert!(fabric.radius <= tube_home().max_tag_radius);
        match bound.too_large(&fabric) {
            Some(TooLarge::Wide { width, widest, with_pixels }) => {
                assert!((widest - 0.03).abs() < 1e-12);
                // Three pixels at 1.5 m on this camera: 1.8 cm.
                assert!((with_pixels - (0.03 + 3.0 * 1.5 / 250.0)).abs() < 1e-9);
                // 8 cm, leaning 20° away: 7.5 cm or more.
                assert!(width > 0.073 && width < 0.081, "{width}");
            }
            other => panic!("the fabric was let in: {other:?}"),
        }
        // Farther away the pixels are wider, and the slack with them: at 6 m the fabric's
        // 7.5 cm is within the tube's 3 cm and three pixels of 2.4 cm each.
        let far = rectangle(0.12, 0.08, 30.0, 20.0, 6.0);
        assert_eq!(bound.too_large(&far), None);
    }

    #[test]
    fn a_red_strip_as_narrow_as_the_tag_but_longer_than_its_diagonal_is_no_tag() {
        // A flip switch's 4.4 × 3 cm foam tube; the face of a red box seen nearly edge on
        // beside it, a strip 2.5 × 10 cm. The strip reaches 5.2 cm from its middle, within the
        // tube's 2.7 cm and a fragment's gap, and is narrower than the tube.
        let home =
            TagSearchParams::default().for_home_tags([TagSize { width: 0.044, height: 0.03 }]);
        let bound = TagBound::new(&home, &camera());
        let strip = rectangle(0.025, 0.10, 0.0, 0.0, 1.5);
        assert!(strip.radius <= home.max_tag_radius);
        match bound.too_large(&strip) {
            Some(TooLarge::Long { length, longest, with_pixels }) => {
                assert!((longest - 0.044f64.hypot(0.03)).abs() < 1e-12);
                assert!((with_pixels - (longest + 3.0 * 1.5 / 250.0)).abs() < 1e-9);
                // 10 cm, less the 2 % of its points left off each end.
                assert!(length > 0.095 && length <= 0.10, "{length}");
            }
            other => panic!("the strip was let in: {other:?}"),
        }
        // The tube itself, turned and leaning any way, is never as long as its diagonal.
        for turn in [0.0, 35.0, 90.0] {
            for lean in [0.0, 60.0] {
                let tube = rectangle(0.044, 0.03, turn, lean, 1.5);
                assert_eq!(bound.too_large(&tube), None, "turned {turn}°, leaning {lean}°");
            }
        }
    }

    #[test]
    fn without_registered_sizes_only_the_reach_bounds_a_tag() {
        let params = TagSearchParams { max_tag_radius: 0.1, ..TagSearchParams::default() };
        let bound = TagBound::new(&params, &camera());
        assert_eq!(bound.too_large(&rectangle(0.12, 0.08, 0.0, 0.0, 1.5)), None);
        let towel = rectangle(0.3, 0.2, 0.0, 0.0, 1.5);
        assert!(matches!(bound.too_large(&towel), Some(TooLarge::Across { .. })));
        assert!(!bound.holds(&towel));
    }
}
