//! An RGB-D camera's depth, aligned to the colour camera as RealSense's `aligned_depth_to_color`
//! has it: one ray per colour pixel, through the same pixel centre, noise-free. Beside it, the
//! very points those rays met, in the base frame: the cloud that depth image stands for, made
//! without converting depth, so the conversion can be checked against it.

use std::path::Path;

use nalgebra::{Isometry3, Point3, Vector3};

use super::capture::SceneCapture;
use super::room::Room;
use crate::hal::PointCloud;
use crate::sensor_files::{
    PlyFormat, SensorFileError, write_depth_pfm, write_depth_png, write_ply,
};

/// Farthest surface the depth camera sees, metres.
const FAR: f32 = 50.0;

/// A depth frame and the cloud of the same rays.
#[derive(Debug, Clone, PartialEq)]
pub struct AlignedDepth {
    pub width: u32,
    pub height: u32,
    /// Distance along the optical axis per pixel, rows top to bottom, metres; NaN where the ray
    /// met nothing.
    pub metres: Vec<f32>,
    /// Where each ray that met something met it, base frame, in pixel order.
    pub cloud: PointCloud,
}

impl AlignedDepth {
    /// What the depth camera beside the colour camera of `capture` sees in `room`.
    pub fn of(capture: &SceneCapture, room: &Room) -> Self {
        let k = &capture.calibration.intrinsics;
        let world_from_base = Isometry3::new(
            Vector3::new(
                capture.world_from_base.translation.x,
                capture.world_from_base.translation.y,
                0.0,
            ),
            Vector3::z() * capture.world_from_base.rotation.angle(),
        );
        let world_from_camera: Isometry3<f32> =
            (world_from_base * capture.calibration.base_from_camera).cast();
        let base_from_world: Isometry3<f32> = world_from_base.inverse().cast();
        let origin = Point3::from(world_from_camera.translation.vector);
        let axis = world_from_camera.rotation * Vector3::z();
        let mut metres = Vec::with_capacity(k.width as usize * k.height as usize);
        let mut points = Vec::with_capacity(metres.capacity());
        for v in 0..k.height {
            for u in 0..k.width {
                let x = ((f64::from(u) + 0.5 - k.cx) / k.fx) as f32;
                let y = ((f64::from(v) + 0.5 - k.cy) / k.fy) as f32;
                let dir = (world_from_camera.rotation * Vector3::new(x, y, 1.0)).normalize();
                match room.scene.cast(&origin, &dir, FAR) {
                    Some(hit) => {
                        metres.push(hit.distance * dir.dot(&axis));
                        points.push(base_from_world * hit.point);
                    }
                    None => metres.push(f32::NAN),
                }
            }
        }
        Self { width: k.width, height: k.height, metres, cloud: PointCloud { points } }
    }

    /// Whole millimetres, 0 where there is no depth: a 16-bit depth PNG's samples.
    pub fn millimetres(&self) -> Vec<u16> {
        let to_mm =
            |m: f32| if m.is_finite() { (m * 1e3).round().clamp(0.0, 65535.0) as u16 } else { 0 };
        self.metres.iter().map(|&m| to_mm(m)).collect()
    }

    /// Writes `depth.png` (millimetres), `depth.pfm` (metres) and `depth.ply` (the same rays'
    /// points, base frame) into `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), SensorFileError> {
        let size = (self.width, self.height);
        write_depth_png(&dir.join("depth.png"), size, &self.millimetres())?;
        write_depth_pfm(&dir.join("depth.pfm"), size, &self.metres)?;
        write_ply(&dir.join("depth.ply"), &self.cloud, PlyFormat::BinaryLittleEndian)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::{DepthImage, DepthRange, cloud_from_depth};
    use crate::sim::{CaptureSettings, DeviceKind, StartDirection, capture_scene};

    #[test]
    fn the_depth_turned_into_a_cloud_is_the_cloud_of_the_same_rays() {
        let capture = capture_scene(
            Room::paper(),
            DeviceKind::Drawer,
            StartDirection::Left,
            1.5,
            5,
            &CaptureSettings::small(),
        );
        let depth = AlignedDepth::of(&capture, &Room::paper());
        let image = DepthImage::from_metres(depth.width, depth.height, &depth.metres).unwrap();
        let range = DepthRange { near: 0.0, far: FAR };
        let cloud = cloud_from_depth(&image, &capture.calibration, &range).unwrap();
        assert!(cloud.len() > 70_000, "the room surrounds the camera: {}", cloud.len());
        assert_eq!(cloud.len(), depth.cloud.len());
        let worst = cloud
            .points
            .iter()
            .zip(&depth.cloud.points)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-4, "a point is {worst} m from its ray's hit");
    }
}
