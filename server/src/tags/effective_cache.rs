//! Effective entries kept in memory, serialised and with their ETag, so the robots' hot path
//! costs a hash look-up and no database work.
//!
//! Every change that can alter an effective entry invalidates it before its request returns.
//! A generation counter keeps a slow miss from re-inserting an entry computed before an
//! invalidation that happened while it was being computed.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, RwLock};

use axum::http::HeaderValue;
use bytes::Bytes;

/// One merged entry, ready to send: the ETag is a header value already (checked once, shared
/// by every answer), since this is the robots' hot path.
#[derive(Debug)]
pub struct CachedEffective {
    pub etag: HeaderValue,
    pub body: Bytes,
}

/// Entries kept at most (about 2 kB each), so memory stays bounded with 100,000 tags.
const CAPACITY: usize = 20_000;

/// A cached entry and whether a robot read it since the last eviction.
#[derive(Debug)]
struct Slot {
    entry: Arc<CachedEffective>,
    read: AtomicBool,
}

#[derive(Debug, Default)]
pub struct EffectiveCache {
    /// EPC → robot id → entry.
    entries: RwLock<HashMap<String, HashMap<String, Slot>>>,
    /// How many entries `entries` holds.
    len: AtomicU64,
    generation: AtomicU64,
}

impl EffectiveCache {
    pub fn get(&self, epc: &str, robot: &str) -> Option<Arc<CachedEffective>> {
        let entries = self.entries.read().unwrap_or_else(|e| e.into_inner());
        let slot = entries.get(epc)?.get(robot)?;
        // Only the first read since an eviction writes: the hot path's many readers of one
        // entry then share its cache line instead of bouncing it between cores.
        if !slot.read.load(Ordering::Relaxed) {
            slot.read.store(true, Ordering::Relaxed);
        }
        Some(slot.entry.clone())
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
            self.evict(&mut entries);
        }
        let slot = Slot { entry, read: AtomicBool::new(false) };
        if entries.entry(epc.to_owned()).or_default().insert(robot.to_owned(), slot).is_none() {
            self.len.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Makes room by second chance (the clock algorithm in one sweep): entries no robot read
    /// since the last eviction go, the others stay and lose their mark. When robots read nearly
    /// everything, a quarter goes in the map's arbitrary order.
    fn evict(&self, entries: &mut HashMap<String, HashMap<String, Slot>>) {
        for robots in entries.values_mut() {
            robots.retain(|_, slot| slot.read.swap(false, Ordering::Relaxed));
        }
        entries.retain(|_, robots| !robots.is_empty());
        let mut held: usize = entries.values().map(HashMap::len).sum();
        if held > CAPACITY - CAPACITY / 4 {
            let drop: Vec<String> = entries.keys().take(entries.len() / 4 + 1).cloned().collect();
            for epc in drop {
                held -= entries.remove(&epc).map_or(0, |robots| robots.len());
            }
        }
        self.len.store(held as u64, Ordering::Relaxed);
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
        Arc::new(CachedEffective {
            etag: HeaderValue::from_static("\"e\""),
            body: Bytes::from_static(b"{}"),
        })
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
        assert!(held <= CAPACITY, "{held}");
        assert!(
            cache.get(&format!("E{}", CAPACITY + 99), "r").is_some(),
            "the newest entry is kept"
        );
    }

    #[test]
    fn the_tags_robots_keep_reading_survive_an_eviction() {
        let cache = EffectiveCache::default();
        let hot: Vec<String> = (0..500).map(|n| format!("H{n}")).collect();
        for epc in &hot {
            cache.insert(cache.generation(), epc, "r", cached());
        }
        // A sweep through many other tags fills the cache twice over while the robots keep
        // reading the hot ones.
        for n in 0..2 * CAPACITY {
            cache.insert(cache.generation(), &format!("E{n}"), "r", cached());
            if n % 1000 == 0 {
                for epc in &hot {
                    assert!(cache.get(epc, "r").is_some(), "{epc} evicted after {n} inserts");
                }
            }
        }
        let held = cache.len.load(Ordering::Relaxed) as usize;
        assert!(held <= CAPACITY, "{held}");
        assert_eq!(held, cache.entries.read().unwrap().values().map(HashMap::len).sum::<usize>());
    }
}
