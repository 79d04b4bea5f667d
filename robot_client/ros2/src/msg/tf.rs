//! `tf2_msgs/TFMessage`: what `/tf` and `/tf_static` carry.

use serde::{Deserialize, Serialize};

use super::geometry::TransformStamped;
use super::ros_message;

/// `tf2_msgs/TFMessage`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TfMessage {
    pub transforms: Vec<TransformStamped>,
}
ros_message!(TfMessage, "tf2_msgs", "TFMessage");
