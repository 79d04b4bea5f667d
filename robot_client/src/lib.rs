//! The robot side of PPS-tags: the paper's perception, navigation and manipulation behind
//! hardware traits, with a deterministic simulator so all of it runs without a robot.
//!
//! - [`hal`]: one trait per hardware capability; a real robot or [`sim`] implements them.
//! - [`perception`]: the paper's §III-B, finding the red tag in a registered image and cloud.
//! - [`cores`]: the machine's cores the chain's larger steps are split over.
//! - [`navigation`]: the paper's §IV-B.1 geometry: volume of interest, planes, backing plane,
//!   waypoint, collision check, and which RFID tag was read.
//! - [`sensor_files`]: the files recorded sensor data travels in (PNG, PLY, camera JSON).
//! - [`registry`]: the registry client, its entry cache and the durable trial outbox.
//! - [`rfid`]: real RFID readers (LLRP over TCP, the ThingMagic M5e over serial).
//! - [`behaviors`]: the paper's §IV-B.2 manipulation behaviours, each with its detector.
//! - [`task`]: the paper's four phases end to end, ending in a trial in the registry.
//! - [`sim`]: a seeded room with the paper's five tagged devices, rendered for the sensors.
//! - [`experiment`]: the paper's §V experiment (Table I) in the simulator: the trials, the
//!   simulated person, the scoring, the runner.
//! - [`worker`]: a simulated robot working the registry's task queue (`pps-robot work`).
//! - [`cli`]: the `pps-robot` and `pps-trials` command lines, which only parse and print.
//!
//! The robot's own code (`hal` to `task`) never uses [`sim`] or [`cli`], so it runs on a real
//! robot unchanged; [`experiment`] and [`worker`] use the simulator but not the command line.
//! The simulator, the experiment, the worker and the commands that use them come with the
//! `sim` feature (on by default); a robot's own software, such as the ROS 2 node, leaves it and
//! its physics library out.

pub mod behaviors;
pub mod cli;
pub mod cores;
#[cfg(feature = "sim")]
pub mod experiment;
pub mod hal;
pub mod navigation;
pub mod perception;
pub mod picture;
pub mod registry;
pub mod rfid;
pub mod sensor_files;
#[cfg(feature = "sim")]
pub mod sim;
pub mod task;
pub mod timings;
#[cfg(feature = "sim")]
pub mod worker;
