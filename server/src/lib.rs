//! The PPS-tag registry server.
