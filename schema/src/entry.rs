//! The tag entry: the paper's Fig. 4 made explicit.

use serde::{Deserialize, Serialize};

/// HSV thresholds that segment a PPS-tag in one robot's camera (paper §III-B).
///
/// Hue is in degrees and may wrap around 0 (`[340, 20]` is red); saturation and value are 0..=1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ColorSegmentation {
    pub hue_deg: [f64; 2],
    pub saturation: [f64; 2],
    pub value: [f64; 2],
}

impl Default for ColorSegmentation {
    /// The red of the paper's tags under a camera flash.
    fn default() -> Self {
        Self {
            hue_deg: [340.0, 20.0],
            saturation: [0.6, 1.0],
            value: [0.15, 1.0],
        }
    }
}
