//! Tasks as the registry takes them, whoever asks (DESIGN §8): a caretaker's request checked,
//! whether a robot can run its action, and the task queued. The HTTP routes (`http::tasks`)
//! and the Home Assistant bridge's buttons both ask here.

pub(crate) mod ask;
pub(crate) mod availability;
pub(crate) mod request;
