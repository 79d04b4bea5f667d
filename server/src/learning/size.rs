//! Learning the tags' sizes from confirmed reads (issue 34): a trial a robot sends after its
//! fingers read the tag's EPC carries the size of what it took for the tag on the surface
//! behind it (`tag_size`). From the confirmed real-use trials of one tag, whichever robot sent
//! them, the registry learns the tag's size, so that a home whose caretaker never took a tape
//! measure to its tags still bounds the robots' search by its largest tag.
//!
//! A size a caretaker registered always stands: the learned one fills in only where the entry
//! has none (the effective entry's merge decides that). Runs inside the transaction that
//! records the trials, like the rest of learning.

use pps_schema::{Epc, TagSize};
use serde_json::Value;
use sqlx::AnyConnection;

use super::{LEARNING_WINDOW, median};
use crate::store::learned_sizes::{self, LearnedSize};

/// Fewest measurements a size rests on: with one or two, a single look that joined a red
/// neighbour to the tag (or saw half of it) is the median or half of it; with three, the
/// median is a measurement two others agree with.
pub const MIN_MEASUREMENTS: usize = 3;

/// The smallest and largest width or height a tag may have, metres: the entry schema's bounds.
const BOUNDS: std::ops::RangeInclusive<f64> = 0.01..=1.0;

/// Whether a trial carries what size learning learns from.
pub fn teaches(trial: &Value) -> bool {
    trial.get("tag_size").is_some_and(Value::is_object)
}

/// Learns the size of `epc` anew; true when it changed.
pub async fn update(conn: &mut AnyConnection, epc: &Epc) -> sqlx::Result<bool> {
    let measured = learned_sizes::measurements(conn, epc, LEARNING_WINDOW).await?;
    learned_sizes::store(conn, epc, learn(&measured)).await
}

/// The size `measured` teaches: the median width and the median height, to the millimetre;
/// `None` when they are too few or it would be out of bounds.
pub fn learn(measured: &[TagSize]) -> Option<LearnedSize> {
    if measured.len() < MIN_MEASUREMENTS {
        return None;
    }
    let millimetres = |value: f64| (value * 1000.0).round() / 1000.0;
    let width = millimetres(median(measured.iter().map(|s| s.width).collect())?);
    let height = millimetres(median(measured.iter().map(|s| s.height).collect())?);
    if !(BOUNDS.contains(&width) && BOUNDS.contains(&height)) {
        tracing::warn!(width, height, "a learned tag size is outside its bounds; not learned");
        return None;
    }
    Some(LearnedSize { size: TagSize { width, height }, trials: measured.len() as u64 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn size(width: f64, height: f64) -> TagSize {
        TagSize { width, height }
    }

    #[test]
    fn the_median_of_three_or_more_within_bounds() {
        let patch = [size(0.051, 0.079), size(0.048, 0.082), size(0.2, 0.081)];
        assert_eq!(learn(&patch[..2]), None, "two are too few");
        let learned = learn(&patch).unwrap();
        assert_eq!(learned.size, size(0.051, 0.081), "one look joined a neighbour: outvoted");
        assert_eq!(learned.trials, 3);
        let huge = [size(0.9, 1.2), size(0.95, 1.1), size(0.9, 1.3)];
        assert_eq!(learn(&huge), None, "1.2 m is no tag");
    }
}
