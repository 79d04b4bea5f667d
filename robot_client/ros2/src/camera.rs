//! `sensor_msgs/CameraInfo` and the static transform to the calibration perception reads.

use nalgebra::Isometry3;
use pps_robot::hal::{CameraCalibration, CameraIntrinsics};

use crate::input_error::InputError;
use crate::msg::sensor::CameraInfo;

/// The pinhole intrinsics of `k` (fx, fy, cx, cy) for an image of the info's size.
pub fn intrinsics(info: &CameraInfo) -> Result<CameraIntrinsics, InputError> {
    let k = info.k;
    let (fx, fy, cx, cy) = (k[0], k[4], k[2], k[5]);
    if ![fx, fy, cx, cy].iter().all(|v| v.is_finite()) || fx <= 0.0 || fy <= 0.0 {
        return Err(InputError::CameraInfo(format!(
            "k has focal lengths fx {fx}, fy {fy}; both must be positive (an uncalibrated camera?)"
        )));
    }
    if info.width == 0 || info.height == 0 {
        return Err(InputError::CameraInfo(format!(
            "the image size is {}×{}",
            info.width, info.height
        )));
    }
    Ok(CameraIntrinsics { width: info.width, height: info.height, fx, fy, cx, cy })
}

/// The calibration for an image of `width`×`height` whose optical frame sits at
/// `base_from_camera`.
pub fn calibration(
    info: &CameraInfo,
    base_from_camera: Isometry3<f64>,
    (width, height): (u32, u32),
) -> Result<CameraCalibration, InputError> {
    let intrinsics = intrinsics(info)?;
    if (intrinsics.width, intrinsics.height) != (width, height) {
        return Err(InputError::SizeMismatch {
            info_w: intrinsics.width,
            info_h: intrinsics.height,
            image_w: width,
            image_h: height,
        });
    }
    Ok(CameraCalibration { intrinsics, base_from_camera })
}

/// The camera info of a calibrated pinhole camera without distortion.
pub fn camera_info(
    intrinsics: &CameraIntrinsics,
    header: crate::msg::builtin::Header,
) -> CameraInfo {
    let CameraIntrinsics { width, height, fx, fy, cx, cy } = *intrinsics;
    CameraInfo {
        header,
        height,
        width,
        distortion_model: "plumb_bob".into(),
        d: vec![0.0; 5],
        k: [fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0],
        r: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        p: [fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0],
        ..CameraInfo::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn k_gives_the_intrinsics_and_the_sizes_must_agree() {
        let intrinsics = CameraIntrinsics {
            width: 640,
            height: 480,
            fx: 500.0,
            fy: 510.0,
            cx: 320.5,
            cy: 240.5,
        };
        let info = camera_info(&intrinsics, Default::default());
        let read = calibration(&info, Isometry3::identity(), (640, 480)).unwrap();
        assert_eq!(read.intrinsics, intrinsics);
        let mismatch = calibration(&info, Isometry3::identity(), (1280, 960)).unwrap_err();
        assert!(mismatch.to_string().contains("640×480"), "{mismatch}");
        let uncalibrated = CameraInfo { width: 640, height: 480, ..CameraInfo::default() };
        assert!(matches!(intrinsics_of(&uncalibrated), Err(InputError::CameraInfo(_))));
    }

    fn intrinsics_of(info: &CameraInfo) -> Result<CameraIntrinsics, InputError> {
        intrinsics(info)
    }
}
