//! The robots' trials as every layer speaks of them, below the store that takes them: which
//! trials a list or an export wants, which ones a success rate counts, the picture one carries.
//! What is done with trials over time (writing, ageing, exporting) stands above the store, in
//! `trial_history`.

pub mod counted_purposes;
pub mod filter;
pub mod picture;
