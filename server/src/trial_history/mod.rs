//! The trial history: every trial written durably, many robots' in one commit, kept for good
//! while its raw data ages out, and exported for analysis outside the registry. It works on
//! the store; the values the store takes about trials are `trials`, below it.

pub mod export;
pub mod retention;
pub mod writer;
