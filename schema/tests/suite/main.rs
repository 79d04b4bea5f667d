//! The contract's tests, one binary: each module was a test file of its own (linking one
//! binary for each cost more than running them).

mod behavior_defaults;
mod hostile_input;
mod robot_validation;
mod seeds;
mod tag_validation;
mod titles;
mod trial_validation;
