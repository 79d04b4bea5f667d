//! The ROS 2 node's tests, one binary: each module was a test file of its own (linking one
//! binary for each cost more than running them). The tests that speak DDS re-run themselves
//! inside a loopback-only network namespace (`support::netns`).

mod cdr_fixtures;
mod click_chain;
mod depth_over_dds;
mod interop;
mod sim_robot;
mod support;
