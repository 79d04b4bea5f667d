//! A message as one serialized payload of the ROS 2 DDS mapping: the 4-byte encapsulation
//! header (plain CDR, little-endian) and the CDR body, exactly as RustDDS puts it on the wire.
//! For tests against captured bytes and for measuring decoding; the node itself lets
//! ros2-client do this.

use byteorder::LittleEndian;
use ros2_client::dds::rustdds::cdr_encoding;

/// The encapsulation header of little-endian plain CDR (XCDR1), options zero.
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// The payload of `message`.
pub fn encode<M: serde::Serialize>(message: &M) -> Result<Vec<u8>, String> {
    let body = cdr_encoding::to_vec::<M, LittleEndian>(message).map_err(|e| e.to_string())?;
    Ok([&CDR_LE_HEADER[..], &body].concat())
}

/// The message in `payload`, or why it is not one.
pub fn decode<M: serde::de::DeserializeOwned>(payload: &[u8]) -> Result<M, String> {
    let (header, body) = payload
        .split_at_checked(4)
        .ok_or("a payload is at least its 4-byte encapsulation header")?;
    if header[..2] != CDR_LE_HEADER[..2] {
        return Err(format!(
            "encapsulation {:02x}{:02x} is not little-endian plain CDR",
            header[0], header[1]
        ));
    }
    let (message, _) =
        cdr_encoding::from_bytes::<M, LittleEndian>(body).map_err(|e| e.to_string())?;
    Ok(message)
}
