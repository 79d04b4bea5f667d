//! The files recorded sensor data travels in: the colour image as PNG, the laser cloud as PLY
//! (base frame, metres), an RGB-D camera's aligned depth image as 16-bit PNG (millimetres) or
//! PFM (metres) and the camera calibration as JSON (DESIGN §6, §10).
//!
//! Readers here check what they read and say what is wrong in words a person can act on; they
//! never panic on bad input. An image's size is checked against [`MAX_IMAGE_PIXELS`] and, when
//! the caller knows the calibration, against it, from the header before any pixel is decoded:
//! a small file may declare a huge image. They know nothing of perception or of the simulator.

mod camera_file;
mod depth_file;
mod image_png;
mod ply;

pub use camera_file::{CameraFile, read_camera_file, write_camera_file};
pub use depth_file::{read_depth, write_depth_pfm, write_depth_png};
pub use image_png::{encode_png, read_png, read_png_of_size, write_png};
pub use ply::{PlyFormat, read_ply, read_ply_from, write_ply, write_ply_to};

/// Why a recorded file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum SensorFileError {
    // The reason is in the message, and so not also a `source()`: a caller printing the
    // error's chain would say it twice.
    #[error("{path}: {reason}")]
    Io { path: String, reason: std::io::Error },
    #[error("{path}: not a PLY point cloud we can read: {reason}")]
    Ply { path: String, reason: String },
    #[error("{path}: not a PNG image we can read: {reason}")]
    Png { path: String, reason: String },
    #[error("{path}: not a camera calibration: {reason}")]
    Camera { path: String, reason: String },
    #[error(
        "{path}: not a depth image we can read (a 16-bit greyscale PNG in millimetres or a \
         greyscale PFM in metres): {reason}"
    )]
    Depth { path: String, reason: String },
    /// The image's header declares a size the calibration or the pixel cap does not allow.
    #[error("{path}: {reason}")]
    Size { path: String, reason: String },
}

/// Most pixels a colour or depth image may have: 4096×4096, four times a 4K camera's frame. A
/// PNG of a few kilobytes can declare 30000×30000, which would take gigabytes to decode.
pub const MAX_IMAGE_PIXELS: u64 = 4096 * 4096;

/// Checks the size an image's header declares, before its pixels are decoded: within
/// [`MAX_IMAGE_PIXELS`] and, when given, the calibration's `expected` size.
pub(crate) fn check_declared_size(
    path: &std::path::Path,
    declared: (u32, u32),
    expected: Option<(u32, u32)>,
) -> Result<(), SensorFileError> {
    let size_error =
        |reason: String| SensorFileError::Size { path: path.display().to_string(), reason };
    let (width, height) = declared;
    if let Some((w, h)) = expected
        && (w, h) != declared
    {
        return Err(size_error(format!(
            "the image is {width}×{height} pixels but the camera calibration is for {w}×{h}"
        )));
    }
    if u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS {
        return Err(size_error(format!(
            "it declares {width}×{height} pixels, more than the {MAX_IMAGE_PIXELS} (4096×4096) \
             an image may have"
        )));
    }
    Ok(())
}

pub(crate) fn io_error(path: &std::path::Path, reason: std::io::Error) -> SensorFileError {
    SensorFileError::Io { path: path.display().to_string(), reason }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    #[test]
    fn a_declared_size_is_held_to_the_cap_and_to_the_camera() {
        let path = Path::new("image.png");
        let check = |declared, expected| {
            check_declared_size(path, declared, expected).map_err(|e| e.to_string())
        };
        assert_eq!(check((4096, 4096), None), Ok(()));
        assert_eq!(check((640, 480), Some((640, 480))), Ok(()));
        let huge = check((30000, 30000), Some((30000, 30000))).unwrap_err();
        assert!(huge.contains("declares 30000×30000 pixels, more than the 16777216"), "{huge}");
        // A width times a height that overflows 32 bits is no way around the cap.
        assert!(check((u32::MAX, u32::MAX), None).is_err());
        assert!(check((4097, 4096), None).is_err());
        let other = check((640, 480), Some((1280, 720))).unwrap_err();
        assert!(other.contains("640×480 pixels but the camera calibration is for 1280×720"));
    }
}
