//! The whole robot as it sweeps the room, in plan view: the base, and the arm and hand standing
//! out ahead of it. The base is taken as its own model for the waypoint's check takes it
//! ([`RobotFootprint`]): a box from the floor to the body's height, so air above ground the base
//! swept is air it swept too. The hand is a box about the carriage's height, reaching from the
//! base's front to the fingertips: the air it swept at one height says nothing of another (a
//! shelf's edge below a switch), so the hand's sweep counts only at the heights it was at.
//!
//! The arm's extension is comparable at any length: a hand drawn in stays inside the box the
//! extended arm swept from the base's front out, at the same height. The hand is as wide as the
//! footprint says the arm and hand are (`arm_half_width`, 6 cm either side for EL-E), which
//! holds the fingers open up to about 50° and around a held object (3 cm either side in the
//! simulator); the task closes them before it reaches for a tag unless they hold something.

use nalgebra::Point2;

use crate::behaviors::RobotBody;
use crate::hal::PlanarPose;
use crate::navigation::RobotFootprint;

/// How far the outline may reach beyond the ground it covered, metres: about what odometry
/// drifts sideways over a metre there and back (0.6–2.7 cm in the simulator), so within what
/// the trail itself is known to.
pub(super) const SLACK: f64 = 0.02;

/// How far the hand's heights may differ from those it swept, metres: what a carriage's encoder
/// knows its height to is far finer; a centimetre keeps the comparison from rounding.
const HEIGHT_SLACK: f64 = 0.01;

/// How far apart the points of the outline checked against the ground are, metres.
const OUTLINE_SPACING: f64 = 0.025;

/// The robot's parts as the sweep tells them apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Outline {
    /// Half length (along the heading) and half width of the base, metres.
    base_half_length: f64,
    base_half_width: f64,
    /// From the base's centre to the fingertips with the arm drawn in, metres.
    hand_ahead: f64,
    /// Half width and half height of the arm and hand, metres.
    hand_half_width: f64,
    hand_half_height: f64,
}

impl Outline {
    /// The outline the robot's configuration describes: the footprint's base and arm, the body's
    /// palm and fingers.
    pub(crate) fn of(footprint: &RobotFootprint, body: &RobotBody) -> Self {
        Self {
            base_half_length: footprint.base_half_length,
            base_half_width: footprint.base_half_width,
            hand_ahead: body.palm_ahead + body.finger_length,
            hand_half_width: footprint.arm_half_width,
            hand_half_height: footprint.arm_half_height,
        }
    }
}

/// Where the robot's parts are: the base's pose (odometry frame), the carriage's height and the
/// arm's extension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stance {
    pub base: PlanarPose,
    pub height: f64,
    pub extension: f64,
}

/// What the robot fills at one step of a motion: the base at `base`, the arm out to `extension`,
/// and the hand over the heights from `low` to `high` (a carriage moving sweeps them all).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Swept {
    pub base: PlanarPose,
    pub extension: f64,
    pub low: f64,
    pub high: f64,
}

impl Swept {
    /// The robot standing still in `stance`.
    pub(crate) fn standing(stance: &Stance) -> Self {
        Self {
            base: stance.base,
            extension: stance.extension,
            low: stance.height,
            high: stance.height,
        }
    }
}

/// The points of the base and of the hand, base frame, a grid [`OUTLINE_SPACING`] apart.
struct Points {
    base: Vec<Point2<f64>>,
    hand: Vec<Point2<f64>>,
}

impl Outline {
    /// How far the hand reaches from the base's centre with the arm out `extension`, metres.
    fn hand_reach(&self, extension: f64) -> f64 {
        self.hand_ahead + extension.max(0.0)
    }

    fn points(&self, extension: f64) -> Points {
        let (l, w) = (self.base_half_length, self.base_half_width);
        let grid = |x0: f64, x1: f64, half: f64| {
            let nx = ((x1 - x0) / OUTLINE_SPACING).ceil().max(1.0) as usize;
            let ny = (2.0 * half / OUTLINE_SPACING).ceil().max(1.0) as usize;
            let mut points = Vec::with_capacity((nx + 1) * (ny + 1));
            for i in 0..=nx {
                for j in 0..=ny {
                    let x = x0 + (x1 - x0) * i as f64 / nx as f64;
                    points.push(Point2::new(x, -half + 2.0 * half * j as f64 / ny as f64));
                }
            }
            points
        };
        let reach = self.hand_reach(extension);
        Points {
            base: grid(-l, l, w),
            hand: if reach > l { grid(l, reach, self.hand_half_width) } else { Vec::new() },
        }
    }

    /// Whether `point` (odometry frame) lies inside the base's outline at `at`, give or take
    /// [`SLACK`].
    fn in_base(&self, at: &PlanarPose, point: &Point2<f64>) -> bool {
        let p = at.inverse_transform_point(point);
        p.x.abs() <= self.base_half_length + SLACK && p.y.abs() <= self.base_half_width + SLACK
    }

    /// Whether `point` (odometry frame) lies inside the hand's outline of `swept`.
    fn in_hand(&self, swept: &Swept, point: &Point2<f64>) -> bool {
        let p = swept.base.inverse_transform_point(point);
        p.x >= self.base_half_length - SLACK
            && p.x <= self.hand_reach(swept.extension) + SLACK
            && p.y.abs() <= self.hand_half_width + SLACK
    }

    /// How far apart two base poses may be and their outlines still share a point, metres.
    fn near(&self, extension: f64) -> f64 {
        let base = self.base_half_length.hypot(self.base_half_width);
        let hand = self.hand_reach(extension).hypot(self.hand_half_width);
        2.0 * base.max(hand) + SLACK
    }

    /// Whether what the robot fills at `step` lies inside what it filled at the steps of
    /// `swept`: every point of the base's outline inside the base's at some step, and every
    /// point of the hand's inside the base's at some step or inside the hand's at a step
    /// whose heights held all the hand's heights now.
    pub(crate) fn covered(&self, swept: &[Swept], step: &Swept) -> bool {
        let centre = step.base.translation.vector;
        let near: Vec<&Swept> = swept
            .iter()
            .filter(|s| {
                (s.base.translation.vector - centre).norm() <= self.near(s.extension.max(0.0))
            })
            .collect();
        let (low, high) = (step.low - self.hand_half_height, step.high + self.hand_half_height);
        let held = |s: &Swept| {
            s.low - self.hand_half_height <= low + HEIGHT_SLACK
                && s.high + self.hand_half_height >= high - HEIGHT_SLACK
        };
        let points = self.points(step.extension);
        points.base.iter().all(|local| {
            let point = step.base * local;
            near.iter().any(|s| self.in_base(&s.base, &point))
        }) && points.hand.iter().all(|local| {
            let point = step.base * local;
            near.iter().any(|s| self.in_base(&s.base, &point) || held(s) && self.in_hand(s, &point))
        })
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry2, Vector2};

    use super::*;

    fn outline() -> Outline {
        Outline::of(&RobotFootprint::default(), &RobotBody::default())
    }

    fn at(x: f64, y: f64, heading_deg: f64, height: f64) -> Swept {
        let base = Isometry2::new(Vector2::new(x, y), heading_deg.to_radians());
        Swept { base, extension: 0.0, low: height, high: height }
    }

    #[test]
    fn the_hand_drawn_in_is_covered_where_the_arm_swept_out_at_its_height() {
        let outline = outline();
        let out = Swept { extension: 0.3, ..at(0.0, 0.0, 0.0, 1.2) };
        assert!(outline.covered(&[out], &at(0.0, 0.0, 0.0, 1.2)));
        // Lowered 20 cm, the drawn-in hand is in air the arm never swept.
        assert!(!outline.covered(&[out], &at(0.0, 0.0, 0.0, 1.0)));
        // Extended farther than it was, it reaches beyond.
        assert!(!outline.covered(&[out], &Swept { extension: 0.4, ..at(0.0, 0.0, 0.0, 1.2) }));
    }

    #[test]
    fn ground_the_base_covered_covers_the_hand_at_any_height() {
        let outline = outline();
        let behind = at(0.0, 0.0, 0.0, 0.8);
        let ahead = at(0.2, 0.0, 0.0, 0.8);
        // Backed 20 cm from where it was, the hand stands inside the base's ground then.
        assert!(outline.covered(&[behind, ahead], &Swept { low: 0.3, high: 1.4, ..behind }));
        // Turned a quarter in place, it sweeps beside the base, never covered.
        assert!(!outline.covered(&[ahead], &at(0.2, 0.0, 90.0, 0.8)));
    }
}
