//! Effective entries kept in memory, serialised and with their ETag, so the robots' hot path
//! costs a hash look-up and no database work.
//!
//! Every change that can alter an effective entry invalidates it before its request returns.
//! A generation counter keeps a slow miss from re-inserting an entry computed before an
//! invalidation that happened while it was being computed.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, RwLock};

use bytes::Bytes;

/// One merged entry, ready to send.
#[derive(Debug)]
pub struct CachedEffective {
    pub etag: String,
    pub body: Bytes,
}

#[derive(Debug, Default)]
pub struct EffectiveCache {
    /// EPC → robot id → entry.
    entries: RwLock<HashMap<String, HashMap<String, Arc<CachedEffective>>>>,
    generation: AtomicU64,
}

impl EffectiveCache {
    pub fn get(&self, epc: &str, robot: &str) -> Option<Arc<CachedEffective>> {
        let entries = self.entries.read().unwrap_or_else(|e| e.into_inner());
        entries.get(epc)?.get(robot).cloned()
    }

    /// The generation to pass to [`Self::insert`]; read it before reading the database.
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::Acquire)
    }

    /// Caches an entry computed from data read at `generation`, unless something was
    /// invalidated since.
    pub fn insert(&self, generation: u64, epc: &str, robot: &str, entry: Arc<CachedEffective>) {
        let mut entries = self.entries.write().unwrap_or_else(|e| e.into_inner());
        if self.generation.load(Ordering::Acquire) == generation {
            entries.entry(epc.to_owned()).or_default().insert(robot.to_owned(), entry);
        }
    }

    /// Forgets every robot's entry for one tag.
    pub fn forget_tag(&self, epc: &str) {
        let mut entries = self.entries.write().unwrap_or_else(|e| e.into_inner());
        self.generation.fetch_add(1, Ordering::AcqRel);
        entries.remove(epc);
    }

    /// Forgets everything (a robot's class or capabilities changed).
    pub fn clear(&self) {
        let mut entries = self.entries.write().unwrap_or_else(|e| e.into_inner());
        self.generation.fetch_add(1, Ordering::AcqRel);
        entries.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cached() -> Arc<CachedEffective> {
        Arc::new(CachedEffective { etag: "\"e\"".into(), body: Bytes::from_static(b"{}") })
    }

    #[test]
    fn an_entry_computed_before_an_invalidation_is_not_cached() {
        let cache = EffectiveCache::default();
        let generation = cache.generation();
        cache.forget_tag("A");
        cache.insert(generation, "A", "r", cached());
        assert!(cache.get("A", "r").is_none());
        cache.insert(cache.generation(), "A", "r", cached());
        assert!(cache.get("A", "r").is_some());
        cache.clear();
        assert!(cache.get("A", "r").is_none());
    }
}
