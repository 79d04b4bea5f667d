//! LLRP's wire format (LLRP 1.0.1 §15–16): big-endian fields, a 10-byte message header, and
//! parameters that are either TLV (6 reserved bits, a 10-bit type, a 16-bit length that counts
//! the header) or TV (a set top bit, a 7-bit type, then a value whose length only the type tells).
//!
//! Decoding never panics and never trusts a length: every read is checked against what is left,
//! and a short or inconsistent buffer is a [`DecodeError`] that says what was being read.

use std::fmt;

/// Bytes in a message header: version and type (2), length (4), message id (4).
pub const MESSAGE_HEADER_LEN: usize = 10;
/// The protocol version we speak: 1 is LLRP 1.0.1, which every LLRP reader accepts.
pub const PROTOCOL_VERSION: u8 = 1;
/// Where a message's length field stops being believable (a report of tens of thousands of tags
/// is a few megabytes).
pub const MAX_MESSAGE_LEN: usize = 16 * 1024 * 1024;

/// Why a message or parameter could not be decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError(pub String);

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for DecodeError {}

pub type Decoded<T> = Result<T, DecodeError>;

/// A message header as it arrives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MessageHeader {
    pub version: u8,
    pub kind: u16,
    /// The whole message's length, header included, bytes.
    pub length: u32,
    pub id: u32,
}

impl MessageHeader {
    /// Reads the header at the start of `bytes`, which must hold at least the header.
    pub fn parse(bytes: &[u8]) -> Decoded<Self> {
        let mut r = FieldReader::new(bytes);
        let first = r.u16("the message header")?;
        let length = r.u32("the message length")?;
        let id = r.u32("the message id")?;
        if (length as usize) < MESSAGE_HEADER_LEN {
            return Err(DecodeError(format!(
                "a message says it is {length} bytes long, shorter than its own 10-byte header"
            )));
        }
        if length as usize > MAX_MESSAGE_LEN {
            return Err(DecodeError(format!(
                "a message says it is {length} bytes long, more than the {MAX_MESSAGE_LEN} bytes \
                 any reader sends"
            )));
        }
        Ok(Self { version: ((first >> 10) & 0x7) as u8, kind: first & 0x3FF, length, id })
    }
}

/// Reads big-endian fields from a byte slice, each read checked against what is left.
#[derive(Debug, Clone)]
pub struct FieldReader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> FieldReader<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    pub fn is_empty(&self) -> bool {
        self.at >= self.bytes.len()
    }

    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    pub fn take(&mut self, n: usize, what: &str) -> Decoded<&'a [u8]> {
        if self.remaining() < n {
            return Err(DecodeError(format!(
                "{what} needs {n} bytes but only {} are left",
                self.remaining()
            )));
        }
        let slice = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(slice)
    }

    fn array<const N: usize>(&mut self, what: &str) -> Decoded<[u8; N]> {
        let mut out = [0; N];
        out.copy_from_slice(self.take(N, what)?);
        Ok(out)
    }

    pub fn u8(&mut self, what: &str) -> Decoded<u8> {
        Ok(self.array::<1>(what)?[0])
    }

    pub fn i8(&mut self, what: &str) -> Decoded<i8> {
        Ok(i8::from_be_bytes(self.array(what)?))
    }

    pub fn u16(&mut self, what: &str) -> Decoded<u16> {
        Ok(u16::from_be_bytes(self.array(what)?))
    }

    pub fn i16(&mut self, what: &str) -> Decoded<i16> {
        Ok(i16::from_be_bytes(self.array(what)?))
    }

    pub fn u32(&mut self, what: &str) -> Decoded<u32> {
        Ok(u32::from_be_bytes(self.array(what)?))
    }

    pub fn u64(&mut self, what: &str) -> Decoded<u64> {
        Ok(u64::from_be_bytes(self.array(what)?))
    }

    /// An `utf8v` field: a 16-bit byte count, then UTF-8 (invalid bytes are replaced, since a
    /// reader's error text is still worth showing).
    pub fn utf8v(&mut self, what: &str) -> Decoded<String> {
        let n = self.u16(what)? as usize;
        Ok(String::from_utf8_lossy(self.take(n, what)?).into_owned())
    }

    /// The next parameter, or `None` at the end of the enclosing body.
    pub fn param(&mut self) -> Decoded<Option<Param<'a>>> {
        if self.is_empty() {
            return Ok(None);
        }
        let first = self.u8("a parameter's type")?;
        if first & 0x80 != 0 {
            let kind = first & 0x7F;
            let Some(len) = tv_value_len(kind) else {
                return Err(DecodeError(format!(
                    "TV parameter type {kind} is not one LLRP 1.1 defines, so its length and \
                     everything after it are unknown"
                )));
            };
            let body = self.take(len, "a TV parameter's value")?;
            return Ok(Some(Param { kind: u16::from(kind), tv: true, body }));
        }
        let second = self.u8("a parameter's type")?;
        let kind = (u16::from(first & 0x03) << 8) | u16::from(second);
        let len = self.u16("a parameter's length")? as usize;
        if len < 4 {
            return Err(DecodeError(format!(
                "TLV parameter type {kind} says it is {len} bytes long, shorter than its header"
            )));
        }
        let body = self.take(len - 4, "a TLV parameter's body")?;
        Ok(Some(Param { kind, tv: false, body }))
    }
}

/// One parameter: its type and its body (the value after the type, and after the length for
/// TLVs).
#[derive(Debug, Clone, Copy)]
pub struct Param<'a> {
    pub kind: u16,
    pub tv: bool,
    pub body: &'a [u8],
}

impl<'a> Param<'a> {
    pub fn fields(&self) -> FieldReader<'a> {
        FieldReader::new(self.body)
    }
}

/// The value lengths of LLRP 1.1's TV parameters (1.0.1's are the first 18).
fn tv_value_len(kind: u8) -> Option<usize> {
    Some(match kind {
        1 => 2,            // AntennaID
        2..=5 => 8,        // First/LastSeenTimestamp UTC/Uptime
        6 => 1,            // PeakRSSI
        7 | 8 => 2,        // ChannelIndex, TagSeenCount
        9 => 4,            // ROSpecID
        10..=12 => 2,      // InventoryParameterSpecID, C1G2-CRC, C1G2-PC
        13 => 12,          // EPC-96
        14 | 15 | 17 => 2, // SpecIndex, ClientRequestOpSpecResult, OpSpecID
        16 => 4,           // AccessSpecID
        18 => 4,           // C1G2SingulationDetails
        19 | 20 => 2,      // C1G2XPCW1, C1G2XPCW2
        _ => return None,
    })
}

/// Writes a message: the header, then whatever `body` writes; the length is filled in after.
pub fn message(kind: u16, id: u32, body: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut out = Vec::with_capacity(64);
    out.extend_from_slice(&((u16::from(PROTOCOL_VERSION) << 10) | (kind & 0x3FF)).to_be_bytes());
    out.extend_from_slice(&[0; 4]);
    out.extend_from_slice(&id.to_be_bytes());
    body(&mut out);
    let len = out.len() as u32;
    out[2..6].copy_from_slice(&len.to_be_bytes());
    out
}

/// Writes a TLV parameter whose body `body` writes; the length is filled in after.
pub fn tlv(out: &mut Vec<u8>, kind: u16, body: impl FnOnce(&mut Vec<u8>)) {
    let start = out.len();
    out.extend_from_slice(&(kind & 0x3FF).to_be_bytes());
    out.extend_from_slice(&[0; 2]);
    body(out);
    let len = (out.len() - start) as u16;
    out[start + 2..start + 4].copy_from_slice(&len.to_be_bytes());
}

/// Writes a TV parameter's type byte; the caller writes its value.
pub fn tv(out: &mut Vec<u8>, kind: u8) {
    out.push(0x80 | kind);
}

pub fn utf8v(out: &mut Vec<u8>, text: &str) {
    let bytes = &text.as_bytes()[..text.len().min(u16::MAX as usize)];
    out.extend_from_slice(&(bytes.len() as u16).to_be_bytes());
    out.extend_from_slice(bytes);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tlv_and_tv_parameters_frame_and_read_back() {
        let mut body = Vec::new();
        tlv(&mut body, 287, |out| out.extend_from_slice(&[0, 0, 0, 0]));
        tv(&mut body, 1);
        body.extend_from_slice(&3u16.to_be_bytes());
        let mut r = FieldReader::new(&body);
        let first = r.param().unwrap().unwrap();
        assert_eq!((first.kind, first.tv, first.body.len()), (287, false, 4));
        let second = r.param().unwrap().unwrap();
        assert_eq!((second.kind, second.tv, second.body), (1, true, &[0u8, 3][..]));
        assert!(r.param().unwrap().is_none());
    }

    #[test]
    fn short_buffers_and_lengths_are_errors_that_say_what() {
        let err = FieldReader::new(&[0x01]).u16("the antenna id").unwrap_err();
        assert_eq!(err.0, "the antenna id needs 2 bytes but only 1 are left");
        // A TLV whose length is under its own header, and one that runs past the buffer.
        assert!(FieldReader::new(&[0x01, 0x1F, 0x00, 0x02]).param().is_err());
        assert!(FieldReader::new(&[0x01, 0x1F, 0x00, 0x08, 0, 0]).param().is_err());
        // A TV type LLRP does not define cannot be skipped.
        let err = FieldReader::new(&[0x80 | 99, 0]).param().unwrap_err();
        assert!(err.0.contains("TV parameter type 99"), "{err}");
        assert!(MessageHeader::parse(&[0x04, 0x3D, 0, 0, 0, 4, 0, 0, 0, 1]).is_err());
    }

    #[test]
    fn a_message_header_carries_version_type_length_and_id() {
        let bytes = message(62, 7, |_| {});
        let header = MessageHeader::parse(&bytes).unwrap();
        assert_eq!(header, MessageHeader { version: 1, kind: 62, length: 10, id: 7 });
    }
}
