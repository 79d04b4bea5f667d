//! `sensor_msgs/Image` depth, aligned to the colour image as RealSense's
//! `aligned_depth_to_color/image_raw` publishes it, to the depth image perception turns into a
//! cloud: `16UC1` (or `mono16`) millimetres, `32FC1` metres, either byte order, rows of any
//! `step`. The message's bytes are taken over, not copied.

use nalgebra::Isometry3;
use pps_robot::hal::PointCloud;
use pps_robot::perception::{DepthEncoding, DepthImage, DepthRange, cloud_from_depth};

use crate::camera::calibration;
use crate::input_error::InputError;
use crate::msg::builtin::Header;
use crate::msg::sensor::{CameraInfo, Image};

/// A depth image as it arrived, with the frame it was taken in.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthFrame {
    pub image: DepthImage,
    /// The optical frame the depth is measured in (the colour camera's, when aligned).
    pub frame_id: String,
}

/// The depth image of a message, or why it cannot be read.
pub fn depth_frame(message: Image) -> Result<DepthFrame, InputError> {
    let big_endian = message.is_bigendian != 0;
    let encoding = match message.encoding.as_str() {
        "16UC1" | "mono16" => DepthEncoding::Millimetres16 { big_endian },
        "32FC1" => DepthEncoding::Metres32 { big_endian },
        other => return Err(InputError::DepthEncoding(other.to_owned())),
    };
    let image = DepthImage::new(
        message.width,
        message.height,
        message.step as usize,
        encoding,
        message.data,
    )
    .map_err(InputError::DepthShape)?;
    let frame_id = message.header.frame_id.trim_start_matches('/').to_owned();
    Ok(DepthFrame { image, frame_id })
}

/// The base-frame cloud of `depth`, taken by the camera `info` describes at `base_from_camera`.
pub fn depth_cloud(
    depth: &DepthFrame,
    info: &CameraInfo,
    base_from_camera: Isometry3<f64>,
) -> Result<PointCloud, InputError> {
    let size = (depth.image.width(), depth.image.height());
    let calibration = calibration(info, base_from_camera, size)?;
    cloud_from_depth(&depth.image, &calibration, &DepthRange::default())
        .map_err(|e| InputError::Perception(e.to_string()))
}

/// Millimetres as `16UC1`, rows unpadded, little-endian: what the simulated robot publishes.
pub fn depth_message(width: u32, height: u32, millimetres: &[u16], header: Header) -> Image {
    Image {
        header,
        height,
        width,
        encoding: "16UC1".into(),
        is_bigendian: 0,
        step: width * 2,
        data: millimetres.iter().flat_map(|d| d.to_le_bytes()).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::camera_info;
    use pps_robot::hal::CameraIntrinsics;

    fn info(width: u32, height: u32) -> CameraInfo {
        let k = CameraIntrinsics { width, height, fx: 2.0, fy: 2.0, cx: 1.0, cy: 1.0 };
        camera_info(&k, Header::default())
    }

    #[test]
    fn sixteen_bit_millimetres_and_float_metres_give_the_same_cloud() {
        let header = Header { frame_id: "/camera_color_optical_frame".into(), ..Header::default() };
        let millimetres = [1000, 0, 2500, 4000];
        let sixteen = depth_frame(depth_message(2, 2, &millimetres, header.clone())).unwrap();
        assert_eq!(sixteen.frame_id, "camera_color_optical_frame");
        // Big-endian rows of two samples padded to 16 bytes.
        let metres: Vec<u8> = [[1.0f32, f32::NAN], [2.5, 4.0]]
            .iter()
            .flat_map(|row| row.iter().flat_map(|m| m.to_be_bytes()).chain([0; 8]))
            .collect();
        let float = Image {
            header,
            height: 2,
            width: 2,
            encoding: "32FC1".into(),
            is_bigendian: 1,
            step: 16,
            data: metres,
        };
        let float = depth_frame(float).unwrap();
        let base_from_camera = Isometry3::translation(0.1, 0.0, 1.2);
        let cloud = depth_cloud(&sixteen, &info(2, 2), base_from_camera).unwrap();
        assert_eq!(cloud.len(), 3);
        assert_eq!(cloud, depth_cloud(&float, &info(2, 2), base_from_camera).unwrap());
    }

    #[test]
    fn other_encodings_short_data_and_other_sizes_are_refused_in_words() {
        let mut message = depth_message(2, 2, &[1000; 4], Header::default());
        message.encoding = "rgb8".into();
        let refused = depth_frame(message).unwrap_err();
        assert!(refused.to_string().contains("`rgb8`; only 16UC1"), "{refused}");
        let mut short = depth_message(2, 2, &[1000; 4], Header::default());
        short.data.truncate(7);
        assert!(matches!(depth_frame(short), Err(InputError::DepthShape(_))));
        let frame = depth_frame(depth_message(2, 2, &[1000; 4], Header::default())).unwrap();
        let refused = depth_cloud(&frame, &info(4, 2), Isometry3::identity()).unwrap_err();
        assert!(matches!(refused, InputError::SizeMismatch { .. }), "{refused}");
    }
}
