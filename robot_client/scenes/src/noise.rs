//! Seeded randomness for the sensor models: one ChaCha stream per sensor and scene, so the same
//! seed always gives the same image and cloud and the two sensors never share draws.
//!
//! Two normal samplers: the exact Marsaglia polar method for the laser (a few hundred thousand
//! draws a sweep), and a cheap Irwin–Hall sum for pixel noise (millions of draws a frame), whose
//! tails stop at ±3.5 σ, which is all an 8-bit pixel can show anyway.

use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A stream of random numbers for one sensor of one scene.
#[derive(Debug, Clone)]
pub struct NoiseSource {
    rng: ChaCha8Rng,
    /// The polar method makes normals in pairs; the second waits here.
    spare: Option<f64>,
}

impl NoiseSource {
    /// The stream `stream` of the scene `seed` (the camera and the laser take different streams).
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(stream);
        Self { rng, spare: None }
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.rng.random()
    }

    /// Uniform in [lo, hi).
    pub fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// A standard normal sample (Marsaglia's polar method).
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        loop {
            let u = 2.0 * self.uniform() - 1.0;
            let v = 2.0 * self.uniform() - 1.0;
            let s = u * u + v * v;
            if s > 0.0 && s < 1.0 {
                let k = (-2.0 * s.ln() / s).sqrt();
                self.spare = Some(v * k);
                return u * k;
            }
        }
    }

    /// An approximately standard normal sample: four 16-bit uniforms from one 64-bit draw,
    /// summed, centred and scaled to unit variance.
    pub fn quick_normal(&mut self) -> f32 {
        let bits = self.rng.next_u64();
        let sum: u32 = (0..4).map(|i| ((bits >> (16 * i)) & 0xffff) as u32).sum();
        // Four uniforms on [0, 1) have mean 2 and variance 1/3.
        const SCALE: f32 = 1.732_050_8 / 65536.0;
        (sum as f32 - 2.0 * 65536.0) * SCALE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moments(samples: impl Iterator<Item = f64>) -> (f64, f64) {
        let v: Vec<f64> = samples.collect();
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64;
        (mean, var.sqrt())
    }

    #[test]
    fn both_normals_have_zero_mean_and_unit_spread() {
        let mut noise = NoiseSource::new(7, 1);
        let (mean, sd) = moments((0..100_000).map(|_| noise.normal()));
        assert!(mean.abs() < 0.02 && (sd - 1.0).abs() < 0.02, "polar: {mean} {sd}");
        let (mean, sd) = moments((0..100_000).map(|_| f64::from(noise.quick_normal())));
        assert!(mean.abs() < 0.02 && (sd - 1.0).abs() < 0.02, "quick: {mean} {sd}");
    }

    #[test]
    fn streams_of_one_seed_differ_and_repeat() {
        let a: Vec<f64> = {
            let mut n = NoiseSource::new(3, 1);
            (0..8).map(|_| n.uniform()).collect()
        };
        let b: Vec<f64> = {
            let mut n = NoiseSource::new(3, 2);
            (0..8).map(|_| n.uniform()).collect()
        };
        let again: Vec<f64> = {
            let mut n = NoiseSource::new(3, 1);
            (0..8).map(|_| n.uniform()).collect()
        };
        assert_ne!(a, b);
        assert_eq!(a, again);
    }
}
