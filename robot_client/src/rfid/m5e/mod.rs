//! The ThingMagic M5e / Mercury embedded serial protocol: [`frame`] is the byte level,
//! [`reader`] the hal implementation.

pub mod frame;
pub mod reader;

pub use reader::{M5eReader, M5eSettings, Region};
