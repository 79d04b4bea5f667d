//! The state every request handler shares.

use std::sync::Arc;

use crate::auth::TokenCache;
use crate::db::Db;

/// Cheap to clone: everything inside is shared.
#[derive(Debug, Clone)]
pub struct AppState {
    pub db: Db,
    pub tokens: Arc<TokenCache>,
}

impl AppState {
    pub fn new(db: Db) -> Self {
        Self { db, tokens: Arc::default() }
    }
}
