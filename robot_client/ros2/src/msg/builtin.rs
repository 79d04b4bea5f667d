//! `builtin_interfaces` and `std_msgs`: time stamps, durations, headers and colours.

use serde::{Deserialize, Serialize};

use super::ros_message;

/// `builtin_interfaces/Time`: seconds and nanoseconds since the epoch (or the robot's clock).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}

impl Time {
    /// The wall clock now, as ROS 2 stamps messages when no simulated clock runs.
    pub fn now() -> Self {
        let since =
            std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
        Self { sec: since.as_secs() as i32, nanosec: since.subsec_nanos() }
    }
}

/// `builtin_interfaces/Duration`; zero means forever where a lifetime is meant.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Duration {
    pub sec: i32,
    pub nanosec: u32,
}

/// `std_msgs/Header`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub stamp: Time,
    pub frame_id: String,
}
ros_message!(Header, "std_msgs", "Header");

/// `std_msgs/ColorRGBA`, each channel 0..1.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ColorRgba {
    pub r: f32,
    pub g: f32,
    pub b: f32,
    pub a: f32,
}
