//! Real RFID readers behind [`crate::hal::RfidReader`]: LLRP over TCP, and the ThingMagic M5e
//! serial reader of the paper's robot. Each turns a reader's own protocol into `(epc, rssi,
//! antenna)` reads; choosing the tag is [`crate::navigation::identify_tag`]'s job, not theirs.

pub mod llrp;
pub mod m5e;
