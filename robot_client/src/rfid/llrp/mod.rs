//! An LLRP client (EPCglobal Low Level Reader Protocol 1.0.1, over TCP): the reader that Impinj,
//! Zebra and most fixed UHF readers speak, behind [`crate::hal::RfidReader`].
//!
//! Layers, bottom up: [`wire`] frames bytes, [`params`] and [`messages`] are the spec's types,
//! [`connection`] carries messages over TCP, [`session`] is the protocol a round needs,
//! [`round_reads`] bounds what a round keeps, and [`reader`] is the hal implementation. Nothing
//! here may block without a deadline, nor hold more than a bounded number of reads.

pub mod connection;
pub mod messages;
pub mod params;
pub mod reader;
pub mod round_reads;
pub mod session;
pub mod settings;
pub mod wire;

pub use connection::LLRP_PORT;
pub use reader::{LlrpReader, tag_read};
pub use settings::{LlrpSettings, RoundStop};
