//! The QoS of each kind of topic, chosen to match what ROS 2 publishers and subscribers of
//! those topics use, since mismatched QoS silently never connects.

use ros2_client::QosProfile;
use ros2_client::qos::{Durability, History};

/// Camera and laser streams: best effort matches both the sensor-data profile drivers use
/// and reliable publishers; only the latest sample matters.
pub fn sensor_stream() -> QosProfile {
    QosProfile::subscription_default().history(History::KeepLast { depth: 1 })
}

/// `/tf_static` as tf2's static broadcaster offers it: reliable and transient local, so a
/// node started late still gets the transforms published once at start-up. Deep enough to
/// keep the last message of many broadcasters.
pub fn latched() -> QosProfile {
    QosProfile::publisher_default()
        .durability(Durability::TransientLocal)
        .history(History::KeepLast { depth: 100 })
}

/// Clicks, inventory rounds, trials and everything the node publishes: reliable, as RViz's
/// tools and Nav2 use, with room for a burst.
pub fn command() -> QosProfile {
    QosProfile::publisher_default().history(History::KeepLast { depth: 10 })
}
