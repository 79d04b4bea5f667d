//! The tilting laser range finder: a planar scanner on a tilting servo, sweeping a point cloud.

use nalgebra::Point3;

use super::HalError;

/// Points in the base frame, metres. `f32` because clouds are large and centimetres matter.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointCloud {
    pub points: Vec<Point3<f32>>,
}

impl PointCloud {
    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

/// How the servo tilts the scan plane through one sweep: from `from` to `to` in steps of `step`,
/// radians, positive tilting the scan plane's forward edge down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TiltSweep {
    pub from: f64,
    pub to: f64,
    pub step: f64,
}

impl TiltSweep {
    /// The tilt angles of the sweep, radians.
    pub fn angles(&self) -> impl Iterator<Item = f64> + '_ {
        let n = if self.step > 0.0 && self.to >= self.from {
            ((self.to - self.from) / self.step).floor() as usize + 1
        } else {
            0
        };
        (0..n).map(move |i| self.from + i as f64 * self.step)
    }
}

/// A laser range finder on a tilting servo (EL-E: a Hokuyo UTM-30LX on a Dynamixel RX-28).
pub trait TiltingLaser: Send + Sync {
    /// Sweeps the scan plane through `sweep` and returns every return, in the base frame.
    fn scan(&self, sweep: &TiltSweep) -> Result<PointCloud, HalError>;
}
