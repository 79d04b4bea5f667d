//! The node's topic names (DESIGN §7) and their remapping, ROS-style `FROM:=TO`, so a robot
//! whose camera publishes on `/head_camera/rgb/image_raw` needs no relay.

use anyhow::Context as _;
use ros2_client::{MessageTypeName, Name, Node, Publisher, QosProfile};

use crate::msg::RosMessage;

/// Every topic the node uses, after remapping.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topics {
    pub image: String,
    pub camera_info: String,
    pub tf_static: String,
    pub points: String,
    pub depth: String,
    pub depth_info: String,
    pub clicked_point: String,
    pub tag_pose: String,
    pub goal_pose: String,
    pub markers: String,
    pub rfid: String,
    pub entry: String,
    pub trial: String,
}

impl Default for Topics {
    fn default() -> Self {
        Self {
            image: "/camera/image_raw".into(),
            camera_info: "/camera/camera_info".into(),
            tf_static: "/tf_static".into(),
            points: "/points".into(),
            // Where RealSense's ROS 2 driver publishes depth aligned to colour.
            depth: "/camera/aligned_depth_to_color/image_raw".into(),
            depth_info: "/camera/aligned_depth_to_color/camera_info".into(),
            clicked_point: "/clicked_point".into(),
            tag_pose: "/pps/tag_pose".into(),
            goal_pose: "/goal_pose".into(),
            markers: "/pps/markers".into(),
            rfid: "/pps/rfid".into(),
            entry: "/pps/entry".into(),
            trial: "/pps/trial".into(),
        }
    }
}

impl Topics {
    /// The topics with each `FROM:=TO` applied; an unknown FROM is an error, so a typo does
    /// not leave the node listening where nothing comes.
    pub fn remapped(remaps: &[String]) -> Result<Self, String> {
        let mut topics = Self::default();
        for remap in remaps {
            let (from, to) =
                remap.split_once(":=").ok_or_else(|| format!("remap `{remap}` is not FROM:=TO"))?;
            let to = absolute(to.trim())?;
            let from = absolute(from.trim())?;
            let slot = topics
                .slots()
                .into_iter()
                .find(|slot| **slot == from)
                .ok_or_else(|| format!("remap `{remap}`: the node has no topic `{from}`"))?;
            *slot = to;
        }
        Ok(topics)
    }

    fn slots(&mut self) -> [&mut String; 13] {
        [
            &mut self.image,
            &mut self.camera_info,
            &mut self.tf_static,
            &mut self.points,
            &mut self.depth,
            &mut self.depth_info,
            &mut self.clicked_point,
            &mut self.tag_pose,
            &mut self.goal_pose,
            &mut self.markers,
            &mut self.rfid,
            &mut self.entry,
            &mut self.trial,
        ]
    }
}

/// A topic name made absolute (the node runs in the root namespace) and checked.
fn absolute(name: &str) -> Result<String, String> {
    let name = if name.starts_with('/') { name.to_owned() } else { format!("/{name}") };
    ros_name(&name)?;
    Ok(name)
}

/// The ROS 2 name of an absolute topic, e.g. `/camera/image_raw` as namespace `/camera`, base
/// `image_raw`.
pub fn ros_name(topic: &str) -> Result<Name, String> {
    let (namespace, base) = topic.rsplit_once('/').unwrap_or(("", topic));
    let namespace = if namespace.is_empty() { "/" } else { namespace };
    Name::new(namespace, base).map_err(|e| format!("`{topic}` is not a ROS 2 topic name: {e}"))
}

/// Subscribes `node` to `topic` (a ROS name such as `/points`) with `qos`.
pub fn subscribe<M: RosMessage>(
    node: &mut Node,
    topic: &str,
    qos: QosProfile,
) -> anyhow::Result<ros2_client::Subscription<M>> {
    let name = ros_name(topic).map_err(anyhow::Error::msg)?;
    let topic_handle = node
        .create_topic(&name, MessageTypeName::new(M::PACKAGE, M::NAME), &qos)
        .with_context(|| format!("cannot create topic {topic}"))?;
    node.create_subscription(&topic_handle, Some(qos))
        .with_context(|| format!("cannot subscribe to {topic}"))
}

/// Creates `node`'s publisher on `topic` (a ROS name such as `/goal_pose`) with `qos`.
pub fn advertise<M: RosMessage>(
    node: &mut Node,
    topic: &str,
    qos: QosProfile,
) -> anyhow::Result<Publisher<M>> {
    let name = ros_name(topic).map_err(anyhow::Error::msg)?;
    let topic_handle = node
        .create_topic(&name, MessageTypeName::new(M::PACKAGE, M::NAME), &qos)
        .with_context(|| format!("cannot create topic {topic}"))?;
    node.create_publisher(&topic_handle, Some(qos))
        .with_context(|| format!("cannot publish on {topic}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn remaps_move_the_named_topic_and_refuse_unknown_ones() {
        let topics = Topics::remapped(&[
            "/camera/image_raw:=/head_camera/rgb/image_raw".into(),
            "points:=/tilt_scan/cloud".into(),
        ])
        .unwrap();
        assert_eq!(topics.image, "/head_camera/rgb/image_raw");
        assert_eq!(topics.points, "/tilt_scan/cloud");
        assert_eq!(topics.goal_pose, "/goal_pose");
        let typo = Topics::remapped(&["/camera/imag_raw:=/x".into()]).unwrap_err();
        assert!(typo.contains("/camera/imag_raw"), "{typo}");
        assert!(Topics::remapped(&["/points".into()]).is_err());
    }

    #[test]
    fn names_split_into_namespace_and_base() {
        let name = ros_name("/camera/image_raw").unwrap();
        assert_eq!(name.to_string(), "/camera/image_raw");
        assert_eq!(ros_name("/goal_pose").unwrap().to_string(), "/goal_pose");
    }
}
