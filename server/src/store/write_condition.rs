//! What a write demands of the stored revision: the store checks it inside the write's own
//! transaction, so two writers racing on one tag cannot both pass. HTTP parses the headers
//! that carry it (`If-Match`, `If-None-Match`); the seeder states its own.

/// What a write request demands of the current state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum WriteCondition {
    /// Only if nothing exists yet (`If-None-Match: *`).
    Absent,
    /// Whatever the current revision (`If-Match: *`).
    AnyRevision,
    /// Only if the current revision is one of these (`If-Match: "rN", ...`).
    Revisions(Vec<i64>),
}

impl WriteCondition {
    pub fn allows(&self, current_revision: i64) -> bool {
        match self {
            Self::Absent => false,
            Self::AnyRevision => true,
            Self::Revisions(revisions) => revisions.contains(&current_revision),
        }
    }
}
