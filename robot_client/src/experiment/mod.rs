//! The paper's experiment (§V, Table I) in the simulator against a registry.
//!
//! The protocol: each device, the robot starting 1.5 m from its tag at the paper's four
//! directions, each action, and the failure cases (unplugged lamp, stuck drawer for pull and for
//! push, sticky object), where a success is a correctly *detected* failure. Randomized, it runs
//! trials drawn from the same rows with random start poses, tag placement and noise. Every
//! trial goes through the robot's outbox into the registry.
//!
//! - `table`: Table I's rows with the paper's figures, and ours printed beside them.
//! - `sampling`: which trials run, the protocol's or random ones.
//! - `trial`: one trial set up as an experimenter would, run, and the room's truth kept.
//! - `person`: the simulated person, who points, picks the action and looks at the room.
//! - `scoring`: whether a trial counts for its row, and why one did not.
//! - `runner`: the whole experiment, until the registry holds every trial.
//! - `real_reader`: the simulated robot with a real RFID reader in its fingers.
//! - `start_up`: the robot's class, and so its simulated body, from the registry.
//!
//! The experiment is the experimenter's side of the simulator, so it uses [`crate::sim`]
//! freely; the robot's side stays [`crate::task::run_task`]. It knows nothing of the command
//! line, which only parses the experiment's settings and prints its table.

mod person;
mod real_reader;
mod runner;
mod sampling;
mod scoring;
mod start_up;
mod table;
mod table_report;
mod trial;

pub use person::achieved;
pub use runner::{flush_until_stored, run_trials};
pub use scoring::TableRow;
pub use start_up::start_up;
pub use table::{Protocol, TABLE_ONE};
pub use table_report::{render_table, rows_json};
pub use trial::{Fault, SimulatedResult, SimulatedTrial, run_simulated, run_simulated_reading};
