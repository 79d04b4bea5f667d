//! Cameras: the colour camera used to find the red tag, and the brightness camera used to see
//! whether a light changed.

use nalgebra::{Isometry3, Point2, Point3};

use super::HalError;

/// An 8-bit sRGB image, rows top to bottom, pixels left to right, `[r, g, b]` per pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct ColorImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl ColorImage {
    /// A black image of the given size.
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, rgb: vec![0; width as usize * height as usize * 3] }
    }

    /// The pixel at column `x`, row `y`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = (y as usize * self.width as usize + x as usize) * 3;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Mean of (r + g + b) / 3 over the image, 0..=255.
    pub fn mean_intensity(&self) -> f64 {
        if self.rgb.is_empty() {
            return 0.0;
        }
        let sum: u64 = self.rgb.iter().map(|&c| u64::from(c)).sum();
        sum as f64 / self.rgb.len() as f64
    }
}

/// An 8-bit grey image, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct GrayImage {
    pub width: u32,
    pub height: u32,
    pub luma: Vec<u8>,
}

impl GrayImage {
    /// Mean intensity over the image, 0..=255.
    pub fn mean_intensity(&self) -> f64 {
        if self.luma.is_empty() {
            return 0.0;
        }
        let sum: u64 = self.luma.iter().map(|&c| u64::from(c)).sum();
        sum as f64 / self.luma.len() as f64
    }
}

/// Pinhole intrinsics in pixels, no distortion (images are rectified). Serialised as the
/// top-level fields of a camera file (DESIGN §6).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraIntrinsics {
    pub width: u32,
    pub height: u32,
    pub fx: f64,
    pub fy: f64,
    pub cx: f64,
    pub cy: f64,
}

impl CameraIntrinsics {
    /// Checks that the numbers make a camera; the reason names the bad field.
    pub fn check(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err("width and height must be positive".into());
        }
        let finite = [self.fx, self.fy, self.cx, self.cy].iter().all(|v| v.is_finite());
        if !finite || self.fx <= 0.0 || self.fy <= 0.0 {
            return Err("fx and fy must be positive numbers, cx and cy finite".into());
        }
        Ok(())
    }

    /// The pixel a point in the optical frame (z out of the lens, x right, y down) falls on, or
    /// `None` when it is behind the camera.
    pub fn project(&self, p: &Point3<f64>) -> Option<Point2<f64>> {
        (p.z > 1e-6)
            .then(|| Point2::new(self.fx * p.x / p.z + self.cx, self.fy * p.y / p.z + self.cy))
    }

    /// The same intrinsics for an image scaled by `factor` (0.25 turns 1280×960 into 320×240).
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            width: (f64::from(self.width) * factor).round() as u32,
            height: (f64::from(self.height) * factor).round() as u32,
            fx: self.fx * factor,
            fy: self.fy * factor,
            cx: self.cx * factor,
            cy: self.cy * factor,
        }
    }
}

/// A calibrated camera: intrinsics, and where the optical frame sits in the base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraCalibration {
    pub intrinsics: CameraIntrinsics,
    /// Maps points from the optical frame (z out of the lens, x right, y down) to the base frame.
    pub base_from_camera: Isometry3<f64>,
}

/// The colour camera registered with the tilting laser (paper §III-B: "taken using the camera's
/// flash").
pub trait ColorCamera: Send + Sync {
    /// Intrinsics and pose of the camera, as calibrated against the laser.
    fn calibration(&self) -> CameraCalibration;

    /// Takes one picture, firing the flash when `flash` is true.
    fn capture(&self, flash: bool) -> Result<ColorImage, HalError>;
}

/// Where the light source whose change a behaviour checks is expected (the entry's `direction`:
/// "up" for switches that control ceiling lights, "forward" for the lamp).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LookDirection {
    Up,
    Forward,
}

/// The camera that watches a light source before and after an action (paper §IV-B.2.b).
pub trait BrightnessCamera: Send + Sync {
    /// A grey picture toward where the light source is expected.
    fn capture_light_source(&self, look: LookDirection) -> Result<GrayImage, HalError>;

    /// Mean intensity (0..=255) of where the light source is expected.
    fn mean_intensity(&self, look: LookDirection) -> Result<f64, HalError> {
        Ok(self.capture_light_source(look)?.mean_intensity())
    }
}
