//! The random draws of one scene: every number a scene is made of comes from its seed's
//! generator, in the order the scene is drawn.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The random draws of one scene.
pub(crate) struct Draw {
    pub(crate) rng: ChaCha8Rng,
}

impl Draw {
    /// Uniform in [lo, hi).
    pub(crate) fn u(&mut self, lo: f64, hi: f64) -> f64 {
        if hi <= lo { lo } else { self.rng.random_range(lo..hi) }
    }

    pub(crate) fn chance(&mut self, p: f64) -> bool {
        self.rng.random_bool(p.clamp(0.0, 1.0))
    }

    pub(crate) fn sign(&mut self) -> f64 {
        if self.chance(0.5) { 1.0 } else { -1.0 }
    }
}
