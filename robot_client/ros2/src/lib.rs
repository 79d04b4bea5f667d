//! A ROS 2 node in pure Rust through which any ROS 2 robot uses the PPS-tag registry and the
//! paper's perception (DESIGN §7): the latest camera image, camera info, static transforms and
//! laser cloud or aligned depth image, and a clicked point, give the tag's pose and a Nav2 goal facing it; an
//! inventory round of the finger readers gives the robot's effective entry for the tag it
//! chose; a trial is recorded through the durable outbox.
//!
//! - [`msg`]: the ROS 2 messages, laid out as ROS 2 Jazzy has them, and `pps_msgs`.
//! - [`image`], [`cloud`], [`depth`], [`camera`], [`transforms`]: ROS 2 messages read into
//!   what `pps-robot`'s perception takes, each refusal an [`InputError`] in words.
//! - [`click`]: a click answered with the paper's chain; [`markers`]: its Fig. 5 for RViz.
//! - [`registry_bridge`]: inventory rounds and trials through `pps-robot`'s registry client;
//!   [`picture`]: which click's view a trial is sent with.
//! - [`node`]: the DDS wiring; [`dds`]: the participant (domain, interface); [`topics`],
//!   [`qos`]: names and QoS.
//!
//! The node never reaches into the simulator: it sees only what a robot publishes.

pub mod camera;
pub mod cdr;
pub mod click;
pub mod cloud;
pub mod dds;
pub mod depth;
pub mod image;
pub mod input_error;
pub mod markers;
pub mod msg;
pub mod node;
pub mod once;
pub mod picture;
pub mod qos;
pub mod registry_bridge;
pub mod topics;
pub mod transforms;

pub use input_error::InputError;
