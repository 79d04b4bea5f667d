//! Effective entries this robot has read, in memory and on disk, so it keeps working from
//! them when the registry is unreachable, also after a restart.
//!
//! An entry is *fresh* while the change feed is connected and has said nothing about its tag
//! (and for at most [`FRESH_FOR`]); a fresh entry is used without asking the registry. Any
//! other entry is revalidated with `If-None-Match` before use.

use std::collections::HashMap;
use std::fs;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::state_file;

/// Longest an entry is trusted without asking, even when no change was announced (a robot's
/// own class or limits changing is not announced to robots).
pub const FRESH_FOR: Duration = Duration::from_secs(60);

/// An entry as stored: the registry's JSON and its ETag.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CachedEntry {
    pub etag: String,
    pub entry: Value,
}

#[derive(Debug)]
struct Slot {
    cached: CachedEntry,
    fresh_until: Option<Instant>,
    /// The change feed announced a change to it (an edit, a learned value) since it was last
    /// confirmed.
    announced: bool,
}

#[derive(Debug)]
pub struct EntryCache {
    dir: PathBuf,
    slots: Mutex<HashMap<String, Slot>>,
}

impl EntryCache {
    /// Opens the cache in `dir`, loading what an earlier run stored (all of it stale).
    pub fn open(dir: impl Into<PathBuf>) -> std::io::Result<Self> {
        let dir = dir.into();
        fs::create_dir_all(&dir)?;
        let mut slots = HashMap::new();
        for entry in fs::read_dir(&dir)? {
            let path = entry?.path();
            let Some(epc) = path.file_stem().and_then(|s| s.to_str()).map(str::to_owned) else {
                continue;
            };
            if path.extension().is_some_and(|e| e == "json")
                && let Some(cached) =
                    fs::read(&path).ok().and_then(|b| serde_json::from_slice(&b).ok())
            {
                slots.insert(epc, Slot { cached, fresh_until: None, announced: false });
            }
        }
        Ok(Self { dir, slots: Mutex::new(slots) })
    }

    /// The cached entry and whether it may be used without asking the registry.
    pub fn get(&self, epc: &str) -> Option<(CachedEntry, bool)> {
        let slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        let slot = slots.get(epc)?;
        let fresh = slot.fresh_until.is_some_and(|until| Instant::now() < until);
        Some((slot.cached.clone(), fresh))
    }

    /// Every cached entry, in no particular order.
    pub fn entries(&self) -> Vec<CachedEntry> {
        let slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        slots.values().map(|slot| slot.cached.clone()).collect()
    }

    /// Stores an entry just confirmed by the registry; `fresh` when the change feed is live.
    pub fn put(&self, epc: &str, cached: CachedEntry, fresh: bool) -> std::io::Result<()> {
        state_file::replace(&self.dir.join(format!("{epc}.json")), &serde_json::to_vec(&cached)?)?;
        let fresh_until = fresh.then(|| Instant::now() + FRESH_FOR);
        self.slots
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(epc.to_owned(), Slot { cached, fresh_until, announced: false });
        Ok(())
    }

    /// Marks an entry confirmed again (a 304) without rewriting it.
    pub fn confirm(&self, epc: &str, fresh: bool) {
        if let Some(slot) = self.slots.lock().unwrap_or_else(|e| e.into_inner()).get_mut(epc) {
            slot.fresh_until = fresh.then(|| Instant::now() + FRESH_FOR);
            slot.announced = false;
        }
    }

    /// The tag is gone (archived, retagged, never registered): forget it.
    pub fn remove(&self, epc: &str) {
        self.slots.lock().unwrap_or_else(|e| e.into_inner()).remove(epc);
        let _ = fs::remove_file(self.dir.join(format!("{epc}.json")));
    }

    /// Forgets every tag not in `registered` (archived or retagged while this robot was away).
    pub fn keep_only(&self, registered: &std::collections::HashSet<String>) {
        let gone: Vec<String> = {
            let slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
            slots.keys().filter(|epc| !registered.contains(*epc)).cloned().collect()
        };
        for epc in gone {
            self.remove(&epc);
        }
    }

    /// The tag changed: ask the registry before using the entry again.
    pub fn invalidate(&self, epc: &str) {
        if let Some(slot) = self.slots.lock().unwrap_or_else(|e| e.into_inner()).get_mut(epc) {
            slot.fresh_until = None;
            slot.announced = true;
        }
    }

    /// The EPCs whose entries the change feed announced changed since they were last confirmed.
    pub fn announced(&self) -> Vec<String> {
        let slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        slots.iter().filter(|(_, slot)| slot.announced).map(|(epc, _)| epc.clone()).collect()
    }

    /// The change feed dropped: nothing can be trusted without asking.
    pub fn invalidate_all(&self) {
        for slot in self.slots.lock().unwrap_or_else(|e| e.into_inner()).values_mut() {
            slot.fresh_until = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_survive_a_restart_as_stale_and_invalidate() {
        let dir = tempfile::tempdir().unwrap();
        let cache = EntryCache::open(dir.path()).unwrap();
        let cached =
            CachedEntry { etag: "\"e1\"".into(), entry: serde_json::json!({ "epc": "A" }) };
        cache.put("A", cached.clone(), true).unwrap();
        assert_eq!(cache.get("A"), Some((cached.clone(), true)));
        cache.invalidate("A");
        assert!(!cache.get("A").unwrap().1);
        cache.confirm("A", true);
        assert!(cache.get("A").unwrap().1);
        let reopened = EntryCache::open(dir.path()).unwrap();
        assert_eq!(reopened.get("A"), Some((cached, false)), "kept on disk, revalidated first");
        reopened.remove("A");
        assert!(EntryCache::open(dir.path()).unwrap().get("A").is_none());
    }

    #[test]
    fn only_what_the_feed_announced_is_read_again_until_confirmed() {
        let dir = tempfile::tempdir().unwrap();
        let cache = EntryCache::open(dir.path()).unwrap();
        let cached = |epc: &str| CachedEntry {
            etag: "\"e1\"".into(),
            entry: serde_json::json!({ "epc": epc }),
        };
        for epc in ["A", "B", "C"] {
            cache.put(epc, cached(epc), true).unwrap();
        }
        cache.invalidate_all();
        assert!(cache.announced().is_empty(), "a dropped feed announces nothing");
        cache.invalidate("B");
        cache.invalidate("C");
        let mut announced = cache.announced();
        announced.sort();
        assert_eq!(announced, ["B", "C"]);
        cache.confirm("B", true);
        cache.put("C", cached("C"), false).unwrap();
        assert!(cache.announced().is_empty());
    }
}
