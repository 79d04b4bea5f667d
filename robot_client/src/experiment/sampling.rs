//! Which trials the experiment runs: the paper's protocol (each row of Table I from the paper's
//! four start directions) or trials drawn at random from the same rows.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::table::TABLE_ONE;
use super::trial::SimulatedTrial;
use crate::sim::{RoomOptions, SimBody, StartDirection};

/// A trial to run and the row of Table I it counts for.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedTrial {
    /// Index into [`TABLE_ONE`].
    pub row: usize,
    pub trial: SimulatedTrial,
}

/// The protocol's trials, or `randomized` random ones, for a robot of `body` in `room`.
pub fn plan(
    seed: u64,
    randomized: Option<usize>,
    body: SimBody,
    room: RoomOptions,
) -> Vec<PlannedTrial> {
    match randomized {
        None => protocol(seed, body, room),
        Some(k) => random(k, seed, body, room),
    }
}

/// Each row from each of the paper's start directions, 1.5 m from the tag.
fn protocol(seed: u64, body: SimBody, room: RoomOptions) -> Vec<PlannedTrial> {
    TABLE_ONE
        .iter()
        .enumerate()
        .flat_map(|(i, p)| {
            StartDirection::PAPER.into_iter().enumerate().map(move |(k, direction)| {
                let trial = SimulatedTrial {
                    start_angle: direction.angle(),
                    seed: seed.wrapping_mul(1000) + (i * 4 + k) as u64,
                    body,
                    room,
                    ..SimulatedTrial::new(p.device, p.action, p.fault)
                };
                PlannedTrial { row: i, trial }
            })
        })
        .collect()
}

/// `k` rows drawn at random, each with a random start pose and tag placement.
fn random(k: usize, seed: u64, body: SimBody, room: RoomOptions) -> Vec<PlannedTrial> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..k)
        .map(|n| {
            let i = rng.random_range(0..TABLE_ONE.len());
            let p = &TABLE_ONE[i];
            let trial = SimulatedTrial {
                // Anywhere on the paper's half-circle and its ends (±67.5°), nearer or further.
                start_angle: rng.random_range(-67.5f64..67.5).to_radians(),
                start_distance: rng.random_range(1.2..2.0),
                // Tags where homes put them: the switches higher or lower, the rocker
                // along the wall (but not over the sideboard, where no robot could stand
                // to reach it), the lamp and the trash can along their walls (clear of the
                // furniture beside them).
                // In a home the switches keep their tags 25–35 cm apart.
                room: RoomOptions {
                    switch_spacing: if room.switch_spacing < 1.0 {
                        rng.random_range(0.25..0.35)
                    } else {
                        rng.random_range(2.2..2.9)
                    },
                    switch_raise: rng.random_range(-0.08..0.08),
                    lamp_along: rng.random_range(4.3..4.7),
                    trash_can_along: rng.random_range(2.35..3.2),
                    ..room
                },
                seed: seed.wrapping_mul(1_000_003) + n as u64,
                body,
                ..SimulatedTrial::new(p.device, p.action, p.fault)
            };
            PlannedTrial { row: i, trial }
        })
        .collect()
}
