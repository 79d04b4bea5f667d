//! The robot's tests, one binary: each module was a test file of its own (linking one binary
//! for each cost more than running them). nextest still runs each test in a process of its own.

mod after_read;
mod back_off;
mod behaviors;
mod learned_colour;
mod learned_sizes;
mod llrp_decoder;
mod llrp_flood;
mod llrp_reader;
#[path = "../llrpkit/mod.rs"]
mod llrpkit;
mod m5e_reader;
mod navigation_scenes;
mod perceive_cli;
mod perception_scenes;
mod registry_client;
mod rfid_cli;
mod robot_classes;
mod sim_mechanics;
mod table_one;
mod tag_sizes;
mod task;
mod work_cli;
mod worker;
