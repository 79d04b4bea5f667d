//! The scene sources' tests, one binary: each module was a test file of its own (linking one
//! binary for each cost more than running them).

mod corpus;
mod generator;
mod organised_frames;
mod touching;
