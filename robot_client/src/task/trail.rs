//! The ground the base covered on its way to the tag, as its own odometry tells it: the pose
//! after each drive and turn since it first looked for the tag, and the outline of the base
//! swept between them; and those drives and turns as they were commanded, for the way back. A base whose camera and laser look ahead knows nothing of the ground
//! behind it except that it came over it; so that ground, and no other, is where it may go
//! backwards.
//!
//! It never decides where to go: [`Trail::covers`] only says whether a pose stays on the ground.

use nalgebra::Point2;

use crate::hal::PlanarPose;
use crate::navigation::RobotFootprint;

/// How far the base's outline may reach beyond the ground it covered, metres: about what its
/// odometry drifts sideways over a metre there and back (0.6–2.7 cm in the simulator), so
/// within what the trail itself is known to.
pub(super) const SLACK: f64 = 0.02;

/// The steps in which the way between two poses of the trail is taken, metres and radians: a
/// 50 cm base turned by a degree moves its corners 6 mm.
const STEP: f64 = 0.01;
const TURN_STEP: f64 = 0.0175;

/// How far apart the points of the outline checked against the ground are, metres.
const OUTLINE_SPACING: f64 = 0.025;

/// One motion of the base as it was commanded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Move {
    /// Straight ahead (negative: back), metres.
    Drive(f64),
    /// In place, counter-clockwise, radians.
    Turn(f64),
}

impl Move {
    /// The motion that undoes this one.
    pub(crate) fn undone(self) -> Self {
        match self {
            Self::Drive(distance) => Self::Drive(-distance),
            Self::Turn(angle) => Self::Turn(-angle),
        }
    }
}

/// The base's odometry poses, oldest first: where it stood when it first looked for the tag,
/// then after each drive and each turn; and those motions as they were commanded.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Trail {
    poses: Vec<PlanarPose>,
    /// `moves[i]` took the base from `poses[i]` to `poses[i + 1]`.
    moves: Vec<Move>,
    /// Which pose the tag was seen from, in the look that led to the waypoint.
    sighting: usize,
    /// The hand's height then, metres: the base turned and drove with the hand there, so the
    /// fingers swept nothing else on the way.
    hand_height: Option<f64>,
}

impl Trail {
    pub(crate) fn starting_at(pose: PlanarPose) -> Self {
        Self { poses: vec![pose], moves: Vec::new(), sighting: 0, hand_height: None }
    }

    /// Adds a motion and where the base stands after it.
    pub(crate) fn push(&mut self, made: Move, pose: PlanarPose) {
        self.moves.push(made);
        self.poses.push(pose);
    }

    /// Notes that the tag was seen from where the base stands now, the hand `hand_height`
    /// metres up.
    pub(crate) fn saw_the_tag(&mut self, hand_height: f64) {
        self.sighting = self.poses.len() - 1;
        self.hand_height = Some(hand_height);
    }

    /// The hand's height when the tag was seen, if it was.
    pub(crate) fn hand_height(&self) -> Option<f64> {
        self.hand_height
    }

    /// The poses from where the base stood when it saw the tag on.
    #[cfg(test)]
    pub(crate) fn since_sighting(&self) -> &[PlanarPose] {
        &self.poses[self.sighting..]
    }

    /// The motions that took the base from where it saw the tag to where it stands.
    pub(crate) fn moves_since_sighting(&self) -> &[Move] {
        &self.moves[self.sighting..]
    }

    /// Whether the base's outline standing at `pose` stays on the ground it covered along the
    /// trail, give or take [`SLACK`]: every point of it, a grid 2.5 cm apart, lies inside the
    /// outline at some pose the base passed through.
    pub(crate) fn covers(&self, footprint: &RobotFootprint, pose: &PlanarPose) -> bool {
        let (l, w) = (footprint.base_half_length, footprint.base_half_width);
        // Outlines whose centres lie farther apart than this cannot share a point.
        let reach = 2.0 * l.hypot(w) + SLACK;
        let near: Vec<PlanarPose> = self
            .path()
            .filter(|p| (p.translation.vector - pose.translation.vector).norm() <= reach)
            .collect();
        let inside = |at: &PlanarPose, point: &Point2<f64>| {
            let p = at.inverse_transform_point(point);
            p.x.abs() <= l + SLACK && p.y.abs() <= w + SLACK
        };
        let (nl, nw) = ((2.0 * l / OUTLINE_SPACING).ceil(), (2.0 * w / OUTLINE_SPACING).ceil());
        (0..=nl as usize).all(|i| {
            (0..=nw as usize).all(|j| {
                let local = Point2::new(-l + 2.0 * l * i as f64 / nl, -w + 2.0 * w * j as f64 / nw);
                let point = pose * local;
                near.iter().any(|at| inside(at, &point))
            })
        })
    }

    /// Every pose the base passed through, in steps, oldest first.
    fn path(&self) -> impl Iterator<Item = PlanarPose> + '_ {
        let first = self.poses.first().copied();
        first.into_iter().chain(self.poses.windows(2).flat_map(|leg| between(&leg[0], &leg[1])))
    }
}

/// The poses on the way from `from` to `to` (a drive or a turn in place), in steps of at most a
/// centimetre and a degree; `from` left out, `to` last.
pub(super) fn between(from: &PlanarPose, to: &PlanarPose) -> impl Iterator<Item = PlanarPose> {
    let (from, to) = (*from, *to);
    let distance = (to.translation.vector - from.translation.vector).norm();
    let angle = (from.rotation.inverse() * to.rotation).angle().abs();
    let steps = ((distance / STEP).max(angle / TURN_STEP).ceil() as usize).max(1);
    (1..=steps).map(move |i| from.lerp_slerp(&to, i as f64 / steps as f64))
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry2, Vector2};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    fn pose(x: f64, y: f64, heading_deg: f64) -> PlanarPose {
        Isometry2::new(Vector2::new(x, y), heading_deg.to_radians())
    }

    /// Drives `distance` along the trail's last heading.
    fn driven(trail: &mut Trail, distance: f64) {
        let last = *trail.since_sighting().last().unwrap();
        trail.push(Move::Drive(distance), last * Isometry2::translation(distance, 0.0));
    }

    fn turned(trail: &mut Trail, degrees: f64) {
        let last = *trail.since_sighting().last().unwrap();
        let angle = degrees.to_radians();
        trail.push(Move::Turn(angle), last * Isometry2::rotation(angle));
    }

    #[test]
    fn every_pose_the_base_passed_through_is_covered() {
        let footprint = RobotFootprint::default();
        let mut rng = ChaCha8Rng::seed_from_u64(34);
        for _ in 0..100 {
            let mut trail = Trail::starting_at(pose(rng.random_range(-2.0..2.0), 0.5, 30.0));
            for _ in 0..3 {
                turned(&mut trail, rng.random_range(-90.0..90.0));
                driven(&mut trail, rng.random_range(0.0..1.0));
            }
            for p in trail.path() {
                assert!(trail.covers(&footprint, &p), "{p:?} along {trail:?}");
            }
        }
    }

    #[test]
    fn straight_back_is_covered_only_as_far_as_the_base_came_straight() {
        let footprint = RobotFootprint::default();
        let mut trail = Trail::starting_at(pose(0.0, 0.0, 0.0));
        driven(&mut trail, 0.8);
        let end = *trail.since_sighting().last().unwrap();
        let back = |d: f64| end * Isometry2::translation(-d, 0.0);
        assert!(trail.covers(&footprint, &back(0.8)));
        assert!(trail.covers(&footprint, &back(0.8 + SLACK)));
        assert!(!trail.covers(&footprint, &back(0.8 + 2.0 * SLACK)));
        // Beside the way it came, though within the slack of its start and end.
        assert!(!trail.covers(&footprint, &pose(0.4, 0.05, 0.0)));
        assert!(trail.covers(&footprint, &pose(0.4, 0.015, 0.0)));
    }

    #[test]
    fn after_a_turn_straight_back_leaves_the_ground_the_base_came_over() {
        let footprint = RobotFootprint::default();
        let mut trail = Trail::starting_at(pose(0.0, 0.0, 0.0));
        driven(&mut trail, 1.0);
        turned(&mut trail, 25.0);
        let end = *trail.since_sighting().last().unwrap();
        // The turn in place is ground covered; 10 cm back along the new heading is not.
        assert!(trail.covers(&footprint, &(end * Isometry2::rotation(-10f64.to_radians()))));
        assert!(!trail.covers(&footprint, &(end * Isometry2::translation(-0.1, 0.0))));
    }
}
