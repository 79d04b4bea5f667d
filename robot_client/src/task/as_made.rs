//! A motion of the base as it was made rather than as it was commanded: a base's drive or turn
//! returns when it is done or when its own safety stopped it (a bumper, a force on the hand),
//! and says which only through odometry. Going back the way it came, a robot that undid a drive
//! stopped partway by its full length would overshoot by what it never drove.

use super::trail::Move;
use crate::hal::PlanarPose;

/// How far odometry may fall short of a drive, or come out beyond it, for the drive to count
/// as made in full: 2 cm or 5 % of it, well beyond odometry's own error (1 % and half a
/// centimetre over a metre in the simulator) and within what stopping short by a bumper takes.
const DRIVE_WHOLE: (f64, f64) = (0.02, 0.05);
/// The same for a turn: 2° or 5 % of it.
const TURN_WHOLE: (f64, f64) = (0.035, 0.05);

/// `commanded` as the base made it, going by odometry from `before` to `after`: the command
/// itself where odometry agrees, otherwise the drive or turn odometry saw. A lift or a reach is
/// told by its joint and is kept as it is.
pub(crate) fn as_made(commanded: Move, before: &PlanarPose, after: &PlanarPose) -> Move {
    let moved = before.inverse() * after;
    let whole = |(least, share): (f64, f64), want: f64, got: f64| {
        (got - want).abs() <= least.max(share * want.abs())
    };
    match commanded {
        Move::Drive(distance) => {
            let driven = moved.translation.x;
            if whole(DRIVE_WHOLE, distance, driven) { commanded } else { Move::Drive(driven) }
        }
        Move::Turn(angle) => {
            // Odometry's angle is within half a turn; the command may be up to one.
            let off = (moved.rotation.angle() - angle + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            let turned = angle + off;
            if whole(TURN_WHOLE, angle, turned) { commanded } else { Move::Turn(turned) }
        }
        Move::Lift { .. } | Move::Reach { .. } => commanded,
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry2, Vector2};

    use super::*;

    #[test]
    fn a_drive_stopped_partway_is_what_odometry_saw() {
        let start = Isometry2::new(Vector2::new(1.0, 2.0), 0.7);
        let whole = start * Isometry2::translation(-0.94 * 1.01, 0.003);
        assert_eq!(as_made(Move::Drive(-0.94), &start, &whole), Move::Drive(-0.94));
        let stopped = start * Isometry2::translation(-0.31, 0.0);
        let Move::Drive(driven) = as_made(Move::Drive(-0.94), &start, &stopped) else { panic!() };
        assert!((driven + 0.31).abs() < 1e-9);
    }

    #[test]
    fn a_turn_stopped_partway_is_what_odometry_saw() {
        let start = Isometry2::new(Vector2::new(1.0, 2.0), 3.0);
        let a = 170f64.to_radians();
        let whole = start * Isometry2::rotation(a * 1.01);
        assert_eq!(as_made(Move::Turn(a), &start, &whole), Move::Turn(a));
        let stopped = start * Isometry2::rotation(-0.5);
        let Move::Turn(turned) = as_made(Move::Turn(-1.2), &start, &stopped) else { panic!() };
        assert!((turned + 0.5).abs() < 1e-9);
    }
}
