//! The registry's SQL, one module per resource. Nothing above this layer writes SQL.

pub mod tags;
pub mod tokens;
