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

/// Entries kept at most (about 2 kB each), so memory stays bounded with 100,000 tags.
const CAPACITY: usize = 20_000;

#[derive(Debug, Default)]
pub struct EffectiveCache {
    /// EPC → robot id → entry.
    entries: RwLock<HashMap<String, HashMap<String, Arc<CachedEffective>>>>,
    /// How many entries `entries` holds.
    len: AtomicU64,
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
        if self.generation.load(Ordering::Acquire) != generation {
            return;
        }
        if self.len.load(Ordering::Relaxed) as usize >= CAPACITY {
            // Full: drop about a quarter of the tags, in the map's arbitrary order. Robots work
            // on a small set of tags at a time, which refills quickly.
            let drop: Vec<String> = entries.keys().take(entries.len() / 4 + 1).cloned().collect();
            for epc in drop {
                if let Some(robots) = entries.remove(&epc) {
                    self.len.fetch_sub(robots.len() as u64, Ordering::Relaxed);
                }
            }
        }
        if entries.entry(epc.to_owned()).or_default().insert(robot.to_owned(), entry).is_none() {
            self.len.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Forgets every robot's entry for one tag.
    pub fn forget_tag(&self, epc: &str) {
        let mut entries = self.entries.write().unwrap_or_else(|e| e.into_inner());
        self.generation.fetch_add(1, Ordering::AcqRel);
        if let Some(robots) = entries.remove(epc) {
            self.len.fetch_sub(robots.len() as u64, Ordering::Relaxed);
        }
    }

    /// Forgets everything (a robot's class or capabilities changed).
    pub fn clear(&self) {
        let mut entries = self.entries.write().unwrap_or_else(|e| e.into_inner());
        self.generation.fetch_add(1, Ordering::AcqRel);
        entries.clear();
        self.len.store(0, Ordering::Relaxed);
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

    #[test]
    fn memory_stays_bounded() {
        let cache = EffectiveCache::default();
        for n in 0..CAPACITY + 100 {
            cache.insert(cache.generation(), &format!("E{n}"), "r", cached());
        }
        let held = cache.len.load(Ordering::Relaxed) as usize;
        assert!(held <= CAPACITY && held > CAPACITY / 2, "{held}");
        assert!(
            cache.get(&format!("E{}", CAPACITY + 99), "r").is_some(),
            "the newest entry is kept"
        );
    }
}
