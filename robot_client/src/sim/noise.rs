//! Seeded randomness for the sensors: Gaussian samples, and a texture that is a pure function of
//! position so the same wood looks the same from every viewpoint.

use rand::Rng;

/// A standard normal sample (Box–Muller).
pub fn gaussian(rng: &mut impl Rng) -> f64 {
    let u: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// The noise of one frame or one sweep: a SplitMix64 stream seeded once from the world's RNG.
/// Hundreds of thousands of draws per frame make a cheap generator worth having; the world's
/// seed still decides every draw.
#[derive(Debug, Clone)]
pub struct SensorNoise {
    state: u64,
    spare: Option<f64>,
}

impl SensorNoise {
    pub fn new(rng: &mut impl Rng) -> Self {
        Self { state: rng.random(), spare: None }
    }

    fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1].
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 / (1u64 << 53) as f64
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform() <= p
    }

    /// A standard normal sample (Box–Muller, both halves used).
    pub fn gaussian(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let (u, v) = (self.uniform(), self.uniform());
        let r = (-2.0 * u.ln()).sqrt();
        let (sin, cos) = (std::f64::consts::TAU * v).sin_cos();
        self.spare = Some(r * sin);
        r * cos
    }
}

/// Wood grain strength at a point, 0..1: thin dark lines along the grain, warped a little.
pub fn wood_grain(x: f32, y: f32, z: f32) -> f32 {
    let warp = 0.6 * (7.0 * z + 3.0 * x).sin() + 0.3 * (13.0 * y - 5.0 * z).sin();
    let phase = 55.0 * (x + 0.7 * y) + 9.0 * z + 4.0 * warp;
    let line = 0.5 + 0.5 * phase.sin();
    line * line * line
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn sensor_noise_is_standard_normal_and_seeded() {
        let mut noise = SensorNoise::new(&mut ChaCha8Rng::seed_from_u64(1));
        let samples: Vec<f64> = (0..100_000).map(|_| noise.gaussian()).collect();
        let mean = samples.iter().sum::<f64>() / samples.len() as f64;
        let var = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / samples.len() as f64;
        assert!(mean.abs() < 0.01 && (var - 1.0).abs() < 0.02, "mean {mean}, variance {var}");
        let mut again = SensorNoise::new(&mut ChaCha8Rng::seed_from_u64(1));
        assert_eq!(again.gaussian(), samples[0]);
    }
}
