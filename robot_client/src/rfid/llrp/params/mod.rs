//! LLRP parameters, one file per part of the spec they come from.

pub mod capabilities;
pub mod config;
pub mod events;
pub mod report;
pub mod rospec;
pub mod status;
