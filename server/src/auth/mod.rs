//! Authentication and authorisation: bearer tokens and browser sessions turned into a
//! [`Principal`], and the role rules of DESIGN §4.
//!
//! Nothing here writes to the database on a successful check: the hot path stays read-only.
//! A check takes what it reads (the token cache, the database, the clock), never the whole
//! state: the state holds this folder's cache and login throttle, so it stands above it.

pub(crate) mod cache;
mod credential;
pub mod login_throttle;
mod principal;
pub mod session;

pub use cache::{RECHECK_AFTER as TOKEN_RECHECK_AFTER, TokenCache};
pub use credential::{Check, authenticate, check_in_memory};
pub use principal::Principal;
