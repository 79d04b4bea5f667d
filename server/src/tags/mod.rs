//! Tags as robots use them: the effective entry (one tag as one robot should use it), the cache
//! that answers it on the hot path, and the paper's five devices the registry starts with.

pub mod effective;
pub mod effective_cache;
pub mod seed;
