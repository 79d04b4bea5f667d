//! Seeded randomness for the sensors: Gaussian samples, and a texture that is a pure function of
//! position so the same wood looks the same from every viewpoint.

use rand::Rng;

/// A standard normal sample (Box–Muller).
pub fn gaussian(rng: &mut impl Rng) -> f64 {
    let u: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// Wood grain strength at a point, 0..1: thin dark lines along the grain, warped a little.
pub fn wood_grain(x: f32, y: f32, z: f32) -> f32 {
    let warp = 0.6 * (7.0 * z + 3.0 * x).sin() + 0.3 * (13.0 * y - 5.0 * z).sin();
    let phase = 55.0 * (x + 0.7 * y) + 9.0 * z + 4.0 * warp;
    let line = 0.5 + 0.5 * phase.sin();
    line * line * line
}
