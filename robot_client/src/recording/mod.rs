//! The files recorded sensor data travels in: the colour image as PNG, the laser cloud as PLY
//! (base frame, metres) and the camera calibration as JSON (DESIGN §6).
//!
//! Readers here check what they read and say what is wrong in words a person can act on; they
//! never panic on bad input. They know nothing of perception or of the simulator.

mod camera_file;
mod image_png;
mod ply;

pub use camera_file::{CameraFile, read_camera_file, write_camera_file};
pub use image_png::{read_png, write_png};
pub use ply::{PlyFormat, read_ply, read_ply_from, write_ply, write_ply_to};

/// Why a recorded file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
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
}

pub(crate) fn io_error(path: &std::path::Path, reason: std::io::Error) -> RecordingError {
    RecordingError::Io { path: path.display().to_string(), reason }
}
