//! The ROS 2 messages the node speaks, field for field in the order of their `.msg` files, so
//! that serde's walk over each struct is exactly the CDR layout ROS 2 puts on the wire.
//!
//! The layouts are those of ROS 2 Jazzy (also Iron and Kilted, whose messages used here are
//! the same); Humble differs only in `visualization_msgs/Marker`, which lacks the texture and
//! mesh-file fields ([`visualization::HumbleMarker`]). `uint8[]` fields are `serde_bytes`, so a 3.7 MB image is one copy rather
//! than four million visits. Nothing here knows perception or the registry.

pub mod builtin;
pub mod geometry;
pub mod pps;
pub mod sensor;
pub mod tf;
pub mod visualization;

/// A message type as ROS 2 names it: package and type, e.g. `sensor_msgs` and `Image`; on the
/// wire `sensor_msgs::msg::dds_::Image_`.
pub trait RosMessage: serde::Serialize + serde::de::DeserializeOwned + 'static {
    const PACKAGE: &'static str;
    const NAME: &'static str;

    /// The DDS type name of the ROS 2 mapping.
    fn dds_type_name() -> String {
        format!("{}::msg::dds_::{}_", Self::PACKAGE, Self::NAME)
    }
}

macro_rules! ros_message {
    ($type:ty, $package:literal, $name:literal) => {
        impl $crate::msg::RosMessage for $type {
            const PACKAGE: &'static str = $package;
            const NAME: &'static str = $name;
        }
        impl ros2_client::Message for $type {}
    };
}
pub(crate) use ros_message;
