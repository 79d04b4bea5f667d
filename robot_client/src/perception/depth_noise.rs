//! How far a range sensor's depths scatter at a given range: the one number every
//! range-dependent tolerance of the chain is sized by.
//!
//! A tilting laser's noise hardly grows over a room's few metres. A stereo or structured-light
//! camera measures disparity `d = f·b/z` with a fixed error of a fraction of a pixel, so its
//! depth error grows with the square of the range: a D435 scatters about a centimetre at 2 m
//! and up to 13 cm at 5 m. Tolerances sized for the laser cut such a surface into slivers and
//! lose it; sized for 5 m they would merge a towel with the front it hangs on at 1 m. So each
//! is the larger of the laser's own value and a multiple of the noise at the tag's range.

/// The standard deviation of a sensor's depth as a function of range: `floor + growth·z²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthNoise {
    /// What does not grow with range, metres: a laser's whole noise.
    pub floor: f64,
    /// Growth with the square of the range, metres of σ per square metre of range.
    pub growth: f64,
}

/// What smoothing a dense frame along its rays brings the noise down to, metres: below the
/// smallest step between a tag and its surface that matters (a towel 2 cm proud).
const SMOOTHED_SIGMA: f64 = 0.01;

/// The widest smoothing block, pixels: at 5 m, 24 pixels of a D435 span 25 cm, about the
/// smallest surface a tag is put on.
const MAX_SMOOTHING_WINDOW: u32 = 24;

/// The largest σ at 1 m a person may state for a depth camera, metres: ten centimetres at 1 m is
/// already half a metre at 2.2 m, no longer a measurement a tag can be found in.
const MAX_SIGMA_AT_ONE_METRE: f64 = 0.1;

/// A stated σ at 1 m that no depth camera has.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error(
    "{0} m is not a depth camera's noise at 1 m: give a σ between 0 and 0.1 m \
     (a RealSense D435 has about 0.0036)"
)]
pub struct NotADepthNoise(pub f64);

impl DepthNoise {
    /// A tilting laser scanner (the paper's Hokuyo): a few millimetres at any range indoors.
    /// Every tolerance sized by it keeps its laser value.
    pub const LASER: Self = Self { floor: 0.004, growth: 0.0 };

    /// A stereo or structured-light camera that matches disparity with a standard deviation of
    /// `disparity_sigma_px` pixels of an imager with focal length `focal_px`, its two views
    /// `baseline_m` apart: `σ(z) = z²·σ_d/(f·b)`. The laser's floor stays under it, for the
    /// surfaces' own texture.
    pub fn disparity(focal_px: f64, baseline_m: f64, disparity_sigma_px: f64) -> Self {
        Self { floor: Self::LASER.floor, growth: disparity_sigma_px / (focal_px * baseline_m) }
    }

    /// A disparity camera given by its σ at 1 m, metres.
    pub fn from_one_metre(sigma_at_one_metre: f64) -> Self {
        Self { floor: Self::LASER.floor, growth: sigma_at_one_metre }
    }

    /// A depth camera by the σ at 1 m a person stated (a flag, a parameter), refused in one
    /// sentence unless it lies in (0, 0.1] metres.
    pub fn stated_at_one_metre(sigma: f64) -> Result<Self, NotADepthNoise> {
        if sigma > 0.0 && sigma <= MAX_SIGMA_AT_ONE_METRE {
            Ok(Self::from_one_metre(sigma))
        } else {
            Err(NotADepthNoise(sigma))
        }
    }

    /// The noise a frame is planned with: the sensor's, when stated; otherwise a D435's when
    /// the frame is a camera's depth image, and a laser's when it is a cloud.
    pub fn stated_or_typical(stated: Option<Self>, depth_image: bool) -> Self {
        match stated {
            Some(noise) => noise,
            None if depth_image => Self::d435(),
            None => Self::LASER,
        }
    }

    /// A RealSense D435 at 848 pixels, 0.08 px subpixel over 447 px × 50 mm: 3.6 mm at 1 m.
    /// `perceive --depth`'s model when none is given.
    pub fn d435() -> Self {
        Self::from_one_metre(0.0036)
    }

    /// σ of a depth measured `range` metres away, metres.
    pub fn sigma_at(&self, range: f64) -> f64 {
        self.floor + self.growth * range * range
    }

    /// The side of the pixel blocks a dense frame is smoothed over at `range` metres
    /// ([`super::RaySmoothing`]): fitting a plane to `w²` points brings σ down by about
    /// `w/√3`, so the side that brings it to a centimetre; 1 (no smoothing) for a laser.
    pub fn smoothing_window(&self, range: f64) -> u32 {
        let side = (3f64.sqrt() * self.sigma_at(range) / SMOOTHED_SIGMA).ceil();
        (side as u32).clamp(1, MAX_SMOOTHING_WINDOW)
    }

    /// σ at `range` metres once smoothed over [`DepthNoise::smoothing_window`], metres.
    pub fn smoothed_sigma_at(&self, range: f64) -> f64 {
        let sigma = self.sigma_at(range);
        match self.smoothing_window(range) {
            1 => sigma,
            side => (3f64.sqrt() * sigma / f64::from(side)).max(self.floor),
        }
    }
}

impl Default for DepthNoise {
    fn default() -> Self {
        Self::LASER
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_disparity_camera_scatters_with_the_square_of_the_range() {
        // A D435 at 848 pixels (focal 447 px, 5 cm baseline, 0.08 px): 1.4 cm at 2 m over
        // the floor.
        let d435 = DepthNoise::disparity(447.0, 0.05, 0.08);
        assert!((d435.sigma_at(2.0) - 0.0183).abs() < 0.0005, "{}", d435.sigma_at(2.0));
        let growth = (d435.sigma_at(4.0) - d435.floor) / (d435.sigma_at(1.0) - d435.floor);
        assert!((growth - 16.0).abs() < 1e-9);
        assert_eq!(DepthNoise::LASER.sigma_at(5.0), DepthNoise::LASER.sigma_at(0.5));
    }

    #[test]
    fn a_stated_noise_is_a_depth_camera_s_or_refused_in_a_sentence() {
        let stated = DepthNoise::stated_at_one_metre(0.0036).unwrap();
        assert_eq!(stated, DepthNoise::d435());
        for bad in [0.0, -0.001, 0.2, f64::NAN, f64::INFINITY] {
            let refused = DepthNoise::stated_at_one_metre(bad).unwrap_err().to_string();
            assert!(refused.contains("between 0 and 0.1 m"), "{bad}: {refused}");
        }
        assert_eq!(DepthNoise::stated_or_typical(None, true), DepthNoise::d435());
        assert_eq!(DepthNoise::stated_or_typical(None, false), DepthNoise::LASER);
        assert_eq!(DepthNoise::stated_or_typical(Some(stated), false), stated);
    }
}
