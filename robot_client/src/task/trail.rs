//! The ground the robot covered on its way to the tag, as its own odometry and joints tell it:
//! where its base stood and where its carriage and arm were after each drive, turn, lift and
//! reach since it first looked for the tag, and what the whole robot ([`Outline`]) swept between
//! them; and those motions as it made them, for the way back. A robot whose camera and laser
//! look ahead knows nothing of the ground behind it except that it came over it; so that ground,
//! and the air its hand swept over it, and no other, is where it may go backwards.
//!
//! The trail starts where the robot first looks for the tag (phase 2), not where it started:
//! the back-off never goes farther from the tag than where it first saw it, and phase 1's drive
//! toward the tag lies farther out than that.
//!
//! It never decides where to go: [`Trail::covers`] only says whether a motion stays on the
//! ground.

use nalgebra::Isometry2;

use super::outline::{Stance, Swept};

/// The steps in which the way between two poses of the trail is taken, metres and radians: a
/// 50 cm base turned by a degree moves its corners 6 mm.
const STEP: f64 = 0.01;
const TURN_STEP: f64 = 0.0175;

/// One motion of the robot as it was made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Move {
    /// Straight ahead (negative: back), metres.
    Drive(f64),
    /// In place, counter-clockwise, radians.
    Turn(f64),
    /// The carriage from one height to another, metres.
    Lift { from: f64, to: f64 },
    /// The arm from one extension to another, metres.
    Reach { from: f64, to: f64 },
}

impl Move {
    /// The motion that undoes this one.
    pub(crate) fn undone(self) -> Self {
        match self {
            Self::Drive(distance) => Self::Drive(-distance),
            Self::Turn(angle) => Self::Turn(-angle),
            Self::Lift { from, to } => Self::Lift { from: to, to: from },
            Self::Reach { from, to } => Self::Reach { from: to, to: from },
        }
    }

    /// Where the robot stands after this motion from `stance`.
    pub(crate) fn after(self, stance: &Stance) -> Stance {
        match self {
            Self::Drive(d) => {
                Stance { base: stance.base * Isometry2::translation(d, 0.0), ..*stance }
            }
            Self::Turn(a) => Stance { base: stance.base * Isometry2::rotation(a), ..*stance },
            Self::Lift { to, .. } => Stance { height: to, ..*stance },
            Self::Reach { to, .. } => Stance { extension: to, ..*stance },
        }
    }
}

/// The robot's stances, oldest first: where it stood when it first looked for the tag, then
/// after each motion; and those motions as they were made.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Trail {
    stances: Vec<Stance>,
    /// `moves[i]` took the robot from `stances[i]` to `stances[i + 1]`.
    moves: Vec<Move>,
    /// Which stance the tag was seen from, in the look that led to the waypoint.
    sighting: usize,
}

impl Trail {
    pub(crate) fn starting_at(stance: Stance) -> Self {
        Self { stances: vec![stance], moves: Vec::new(), sighting: 0 }
    }

    /// Adds a motion and where the robot stands after it.
    pub(crate) fn push(&mut self, made: Move, stance: Stance) {
        self.moves.push(made);
        self.stances.push(stance);
    }

    /// Notes that the tag was seen from where the robot stands now.
    pub(crate) fn saw_the_tag(&mut self) {
        self.sighting = self.stances.len() - 1;
    }

    /// The stances from where the robot stood when it saw the tag on.
    #[cfg(test)]
    pub(crate) fn since_sighting(&self) -> &[Stance] {
        &self.stances[self.sighting..]
    }

    /// The motions that took the robot from where it saw the tag to where it stands.
    pub(crate) fn moves_since_sighting(&self) -> &[Move] {
        &self.moves[self.sighting..]
    }

    /// What the robot filled along the trail, in steps of at most a centimetre and a degree.
    pub(crate) fn swept(&self) -> Vec<Swept> {
        let first = self.stances.first().map(Swept::standing);
        first
            .into_iter()
            .chain(self.stances.windows(2).flat_map(|leg| between(&leg[0], &leg[1])))
            .collect()
    }

    /// Whether every step of `steps` stays inside what the robot filled along the trail.
    #[cfg(test)]
    pub(crate) fn covers(&self, outline: &super::outline::Outline, steps: &[Swept]) -> bool {
        let swept = self.swept();
        steps.iter().all(|step| outline.covered(&swept, step))
    }
}

/// What the robot fills on the way from `from` to `to` (a drive or a turn in place, a lift or a
/// reach), in steps of at most a centimetre and a degree; `from` left out, `to` last. A lift
/// fills every height between; a reach the farther extension.
pub(super) fn between(from: &Stance, to: &Stance) -> Vec<Swept> {
    let (a, b) = (from.base, to.base);
    let distance = (b.translation.vector - a.translation.vector).norm();
    let angle = (a.rotation.inverse() * b.rotation).angle().abs();
    let steps = ((distance / STEP).max(angle / TURN_STEP).ceil() as usize).max(1);
    let (low, high) = (from.height.min(to.height), from.height.max(to.height));
    let extension = from.extension.max(to.extension);
    (1..=steps)
        .map(|i| Swept { base: a.lerp_slerp(&b, i as f64 / steps as f64), extension, low, high })
        .collect()
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry2, Vector2};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::behaviors::RobotBody;
    use crate::navigation::RobotFootprint;
    use crate::task::outline::{Outline, SLACK};

    fn outline() -> Outline {
        Outline::of(&RobotFootprint::default(), &RobotBody::default())
    }

    fn stance(x: f64, y: f64, heading_deg: f64) -> Stance {
        let base = Isometry2::new(Vector2::new(x, y), heading_deg.to_radians());
        Stance { base, height: 0.8, extension: 0.0 }
    }

    /// Makes `made` from the trail's last stance.
    fn made(trail: &mut Trail, made: Move) {
        let last = *trail.since_sighting().last().unwrap();
        trail.push(made, made.after(&last));
    }

    fn standing(trail: &Trail, stance: Stance) -> bool {
        trail.covers(&outline(), &[Swept::standing(&stance)])
    }

    #[test]
    fn every_step_the_robot_made_is_covered() {
        let mut rng = ChaCha8Rng::seed_from_u64(34);
        for _ in 0..20 {
            let mut trail = Trail::starting_at(stance(rng.random_range(-2.0..2.0), 0.5, 30.0));
            for _ in 0..3 {
                made(&mut trail, Move::Turn(rng.random_range(-90f64..90.0).to_radians()));
                made(&mut trail, Move::Drive(rng.random_range(0.0..1.0)));
            }
            made(&mut trail, Move::Lift { from: 0.8, to: rng.random_range(0.3..1.4) });
            made(&mut trail, Move::Reach { from: 0.0, to: rng.random_range(0.0..0.5) });
            assert!(trail.covers(&outline(), &trail.swept()), "{trail:?}");
        }
    }

    #[test]
    fn straight_back_is_covered_only_as_far_as_the_base_came_straight() {
        let mut trail = Trail::starting_at(stance(0.0, 0.0, 0.0));
        made(&mut trail, Move::Drive(0.8));
        let end = *trail.since_sighting().last().unwrap();
        let back = |d: f64| Move::Drive(-d).after(&end);
        assert!(standing(&trail, back(0.8)));
        assert!(standing(&trail, back(0.8 + SLACK)));
        assert!(!standing(&trail, back(0.8 + 2.0 * SLACK)));
        // Beside the way it came, though within the slack of its start and end.
        assert!(!standing(&trail, stance(0.4, 0.05, 0.0)));
        assert!(standing(&trail, stance(0.4, 0.015, 0.0)));
    }

    #[test]
    fn after_a_turn_straight_back_leaves_the_ground_the_robot_came_over() {
        let mut trail = Trail::starting_at(stance(0.0, 0.0, 0.0));
        made(&mut trail, Move::Drive(1.0));
        made(&mut trail, Move::Turn(25f64.to_radians()));
        let end = *trail.since_sighting().last().unwrap();
        // The turn in place is ground covered; 10 cm back along the new heading is not.
        assert!(standing(&trail, Move::Turn(-10f64.to_radians()).after(&end)));
        assert!(!standing(&trail, Move::Drive(-0.1).after(&end)));
    }

    #[test]
    fn a_hand_lowered_where_it_was_never_lowered_leaves_the_air_it_swept() {
        // Hand raised to 1.2 m, then 40 cm ahead: where it stands now it was never at 0.8 m.
        let mut trail = Trail::starting_at(stance(0.0, 0.0, 0.0));
        made(&mut trail, Move::Lift { from: 0.8, to: 1.2 });
        made(&mut trail, Move::Drive(0.4));
        let end = *trail.since_sighting().last().unwrap();
        let lowered = Move::Lift { from: 1.2, to: 0.8 }.after(&end);
        assert!(!trail.covers(&outline(), &between(&end, &lowered)));
        // Back where it was raised, lowering it sweeps what raising it swept.
        let back = Move::Drive(-0.4).after(&end);
        assert!(trail.covers(&outline(), &between(&end, &back)));
        let lowered = Move::Lift { from: 1.2, to: 0.8 }.after(&back);
        assert!(trail.covers(&outline(), &between(&back, &lowered)));
    }
}
