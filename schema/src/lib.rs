//! The PPS-tag contract shared by the registry and the robots: the JSON Schemas in
//! `schemas/`, the serde types that match them, the validator, and the [`Epc`] key.
//!
//! This crate depends on neither the server nor the robot client.

mod entry;
mod epc;

pub use entry::ColorSegmentation;
pub use epc::{Epc, EpcError};
