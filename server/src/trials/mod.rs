//! The robots' trials after they arrive: written durably in groups, filtered for lists and
//! exports, counted by purpose, their pictures checked, their raw data aged out.

pub mod counted_purposes;
pub mod export;
pub mod filter;
pub mod picture;
pub mod retention;
pub mod writer;
