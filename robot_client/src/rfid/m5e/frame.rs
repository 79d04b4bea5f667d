//! ThingMagic's serial framing (Mercury embedded protocol, as the M5e speaks it): a command is
//! `0xFF, length, opcode, data, CRC` and a response `0xFF, length, opcode, status (2), data,
//! CRC`; the length counts only the data, and a CRC-16-CCITT (see [`crc16`], big-endian) covers
//! everything after the 0xFF.

use std::fmt::Write;

/// The byte every frame starts with.
pub const HEADER: u8 = 0xFF;

/// Opcodes the client uses.
pub mod opcode {
    pub const GET_VERSION: u8 = 0x03;
    pub const READ_TAG_MULTIPLE: u8 = 0x22;
    pub const GET_TAG_BUFFER: u8 = 0x29;
    pub const CLEAR_TAG_BUFFER: u8 = 0x2A;
    pub const SET_ANTENNA_PORT: u8 = 0x91;
    pub const SET_READ_TX_POWER: u8 = 0x92;
    pub const SET_TAG_PROTOCOL: u8 = 0x93;
    pub const SET_REGION: u8 = 0x97;
}

/// The status a read answers with when no tag replied: not an error.
pub const NO_TAGS_FOUND: u16 = 0x0400;

/// CRC-16-CCITT (polynomial 0x1021, register starting at 0xFFFF) the way ThingMagic computes
/// it: each data bit, most significant first, shifted into the register with no augmenting
/// zeros. This is not the common table form ("CCITT-FALSE"), which gives other values that a
/// module rejects; ThingMagic's documented version command `FF 00 03 1D 0C` pins the difference.
pub fn crc16(bytes: &[u8]) -> u16 {
    bytes.iter().fold(0xFFFF, |mut crc: u16, &byte| {
        for bit in (0..8).rev() {
            let carry = crc & 0x8000 != 0;
            crc = (crc << 1) | u16::from((byte >> bit) & 1);
            if carry {
                crc ^= 0x1021;
            }
        }
        crc
    })
}

/// A command frame for `opcode` with `data` (at most 255 bytes).
pub fn command(opcode: u8, data: &[u8]) -> Vec<u8> {
    assert!(data.len() <= 255, "a frame carries at most 255 data bytes");
    let mut frame = Vec::with_capacity(data.len() + 5);
    frame.extend_from_slice(&[HEADER, data.len() as u8, opcode]);
    frame.extend_from_slice(data);
    let crc = crc16(&frame[1..]);
    frame.extend_from_slice(&crc.to_be_bytes());
    frame
}

/// A response frame (what a reader sends), for tests and peers.
pub fn response(opcode: u8, status: u16, data: &[u8]) -> Vec<u8> {
    let mut frame = vec![HEADER, data.len() as u8, opcode];
    frame.extend_from_slice(&status.to_be_bytes());
    frame.extend_from_slice(data);
    let crc = crc16(&frame[1..]);
    frame.extend_from_slice(&crc.to_be_bytes());
    frame
}

/// A decoded response.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Response {
    pub opcode: u8,
    pub status: u16,
    pub data: Vec<u8>,
}

/// Bytes in a response frame besides its data: header, length, opcode, status, CRC.
pub const RESPONSE_OVERHEAD: usize = 7;

/// The response in `frame` (one whole frame, from its 0xFF to its CRC), or why it is not one.
pub fn parse_response(frame: &[u8]) -> Result<Response, String> {
    if frame.len() < RESPONSE_OVERHEAD || frame[0] != HEADER {
        return Err(format!("{} is not a response frame", hex(frame)));
    }
    let len = usize::from(frame[1]);
    if frame.len() != len + RESPONSE_OVERHEAD {
        return Err(format!(
            "frame {} says it carries {len} data bytes but is {} bytes long",
            hex(frame),
            frame.len()
        ));
    }
    let body = &frame[1..frame.len() - 2];
    let sent = u16::from_be_bytes([frame[frame.len() - 2], frame[frame.len() - 1]]);
    let computed = crc16(body);
    if sent != computed {
        return Err(format!(
            "bad CRC in frame {}: it says {sent:04X}, its bytes give {computed:04X}",
            hex(frame)
        ));
    }
    Ok(Response {
        opcode: frame[2],
        status: u16::from_be_bytes([frame[3], frame[4]]),
        data: frame[5..5 + len].to_vec(),
    })
}

/// Bytes as spaced upper-case hex, the way the reader's manual prints frames.
pub fn hex(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len() * 3);
    for (i, b) in bytes.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        let _ = write!(out, "{b:02X}");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_crc_is_thingmagics() {
        // The version command as ThingMagic documents it: FF 00 03 1D 0C (the table form of
        // CRC-16-CCITT would end it 2D 6C).
        assert_eq!(command(opcode::GET_VERSION, &[]), [0xFF, 0x00, 0x03, 0x1D, 0x0C]);
    }

    #[test]
    fn responses_parse_and_bad_ones_say_why_with_the_frame() {
        let frame = response(0x93, 0, &[]);
        assert_eq!(parse_response(&frame), Ok(Response { opcode: 0x93, status: 0, data: vec![] }));
        let mut bad = response(0x03, 0, &[1, 2, 3]);
        let last = bad.len() - 1;
        bad[last] ^= 0x55;
        let err = parse_response(&bad).unwrap_err();
        assert!(err.starts_with("bad CRC in frame FF 03 03 00 00 01 02 03"), "{err}");
        assert!(parse_response(&frame[..5]).unwrap_err().contains("not a response frame"));
    }
}
