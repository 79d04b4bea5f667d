//! The DDS participant the node joins ROS 2 with: the domain from `ROS_DOMAIN_ID` (default 0,
//! as ROS 2 has it), and optionally one interface to use and announce (a robot's internal
//! network, or loopback inside an isolated network namespace) instead of every interface.

use std::net::IpAddr;

use ros2_client::Context;
use ros2_client::dds::rustdds::DomainParticipantBuilder;

/// Kernel receive buffer asked for: an image is thousands of fragments arriving at once, and
/// a lost fragment costs a repair round trip.
const RECEIVE_BUFFER_BYTES: usize = 32 * 1024 * 1024;

/// Where and how the node speaks DDS.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DdsSettings {
    pub domain_id: u16,
    /// The only interface used for multicast and announced to peers; all when `None`.
    pub interface: Option<IpAddr>,
}

impl DdsSettings {
    /// The domain from `ROS_DOMAIN_ID`, or why it is not one.
    pub fn domain_from_env() -> Result<u16, String> {
        match std::env::var("ROS_DOMAIN_ID") {
            Err(_) => Ok(0),
            Ok(text) if text.trim().is_empty() => Ok(0),
            Ok(text) => match text.trim().parse::<u16>() {
                Ok(id) if id <= 232 => Ok(id),
                _ => Err(format!("ROS_DOMAIN_ID is `{text}`; it must be a number from 0 to 232")),
            },
        }
    }

    /// A ROS 2 context on a participant with these settings.
    pub fn context(&self) -> Result<Context, String> {
        let mut builder = DomainParticipantBuilder::new(self.domain_id)
            .socket_receive_buffer_size(RECEIVE_BUFFER_BYTES)
            .socket_send_buffer_size(RECEIVE_BUFFER_BYTES);
        if let Some(interface) = self.interface {
            builder = builder.with_only_networks([interface]);
        }
        let participant = builder
            .build()
            .map_err(|e| format!("cannot join DDS domain {}: {e}", self.domain_id))?;
        Context::from_domain_participant(participant)
            .map_err(|e| format!("cannot start ROS 2 on DDS domain {}: {e}", self.domain_id))
    }
}
