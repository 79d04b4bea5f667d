//! `camera.json`: intrinsics and the camera's pose in the base frame (DESIGN §6).

use std::path::Path;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::{SensorFileError, io_error};
use crate::hal::{CameraCalibration, CameraIntrinsics};

/// The JSON document: the intrinsics' own fields at the top level, beside the pose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CameraFile {
    #[serde(flatten)]
    pub intrinsics: CameraIntrinsics,
    pub base_from_camera: PoseFile,
}

/// A pose as JSON: translation in metres, rotation as a unit quaternion `[qx, qy, qz, qw]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoseFile {
    pub translation: [f64; 3],
    pub rotation_xyzw: [f64; 4],
}

impl From<&CameraCalibration> for CameraFile {
    fn from(c: &CameraCalibration) -> Self {
        let q = c.base_from_camera.rotation.quaternion();
        let t = c.base_from_camera.translation.vector;
        Self {
            intrinsics: c.intrinsics,
            base_from_camera: PoseFile {
                translation: [t.x, t.y, t.z],
                rotation_xyzw: [q.i, q.j, q.k, q.w],
            },
        }
    }
}

impl CameraFile {
    /// Checks the numbers and builds the calibration; the reason names the bad field.
    pub fn to_calibration(&self) -> Result<CameraCalibration, String> {
        self.intrinsics.check()?;
        let [x, y, z] = self.base_from_camera.translation;
        let [qx, qy, qz, qw] = self.base_from_camera.rotation_xyzw;
        let q = Quaternion::new(qw, qx, qy, qz);
        if ![x, y, z, qx, qy, qz, qw].iter().all(|v| v.is_finite()) || q.norm() < 1e-9 {
            return Err(
                "base_from_camera needs a finite translation and a non-zero quaternion".into()
            );
        }
        Ok(CameraCalibration {
            intrinsics: self.intrinsics,
            base_from_camera: Isometry3::from_parts(
                Translation3::new(x, y, z),
                UnitQuaternion::from_quaternion(q),
            ),
        })
    }
}

/// Reads and checks a camera file.
pub fn read_camera_file(path: &Path) -> Result<CameraCalibration, SensorFileError> {
    let text = std::fs::read_to_string(path).map_err(|e| io_error(path, e))?;
    let camera_error =
        |reason: String| SensorFileError::Camera { path: path.display().to_string(), reason };
    let file: CameraFile = serde_json::from_str(&text).map_err(|e| camera_error(e.to_string()))?;
    file.to_calibration().map_err(camera_error)
}

/// Writes a camera file, pretty-printed.
pub fn write_camera_file(
    path: &Path,
    calibration: &CameraCalibration,
) -> Result<(), SensorFileError> {
    let text = serde_json::to_string_pretty(&CameraFile::from(calibration))
        .map_err(|e| io_error(path, std::io::Error::other(e)))?;
    std::fs::write(path, text + "\n").map_err(|e| io_error(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn round_trips_through_json() {
        let calibration = CameraCalibration {
            intrinsics: CameraIntrinsics {
                width: 320,
                height: 240,
                fx: 250.0,
                fy: 251.0,
                cx: 160.0,
                cy: 119.5,
            },
            base_from_camera: Isometry3::new(
                Vector3::new(0.1, -0.02, 1.3),
                Vector3::new(0.3, -0.2, 0.1),
            ),
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("camera.json");
        write_camera_file(&path, &calibration).unwrap();
        let back = read_camera_file(&path).unwrap();
        assert_eq!(back.intrinsics, calibration.intrinsics);
        let p = nalgebra::Point3::new(0.3, 0.2, 2.0);
        assert!((back.base_from_camera * p - calibration.base_from_camera * p).norm() < 1e-12);
    }

    #[test]
    fn names_what_is_missing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("camera.json");
        std::fs::write(
            &path,
            r#"{"width":10,"height":10,"fx":1,"fy":1,"cx":1,
               "base_from_camera":{"translation":[0,0,0],"rotation_xyzw":[0,0,0,1]}}"#,
        )
        .unwrap();
        let message = read_camera_file(&path).unwrap_err().to_string();
        assert!(message.contains("cy"), "{message}");
        std::fs::write(
            &path,
            r#"{"width":10,"height":10,"fx":-1,"fy":1,"cx":1,"cy":1,
               "base_from_camera":{"translation":[0,0,0],"rotation_xyzw":[0,0,0,1]}}"#,
        )
        .unwrap();
        let message = read_camera_file(&path).unwrap_err().to_string();
        assert!(message.contains("fx"), "{message}");
    }
}
