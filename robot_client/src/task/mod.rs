//! The task (paper §IV-B): the person points, and the robot (1) drives toward the pointed
//! location until within 1.0 m, (2) finds the tag and drives to a waypoint 50 cm out along the
//! normal of the surface behind it, facing it, (3) moves its fingers to about 10 cm from the tag
//! and reads the tag's RFID, (4) reads the registry's entry for it, chooses the action (asking
//! the person when there are two), runs the behaviour, asks the person whether it worked and
//! records the trial in the registry.
//!
//! The task sees the world through the `hal` traits and the registry through
//! [`RegistryClient`](crate::registry::RegistryClient): never the simulator's state.

mod act;
mod approach;
mod as_made;
mod back_off;
mod config;
mod drive;
mod identify;
mod known_tags;
mod outline;
mod perform;
mod report;
mod run;
mod task_robot;
mod trail;
mod trailing;

pub use act::{ActionChoice, choose_action, vertical_choice_for};
pub use config::TaskConfig;
pub use known_tags::{
    ColourSource, ThisTagSearch, search_for_known_tags, search_for_this_tag,
    search_in_the_registered_colour,
};
pub use report::{PhaseReport, TaskReport};
pub use run::run_task;
pub use task_robot::TaskRobot;
