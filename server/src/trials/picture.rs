//! A trial's picture as the registry accepts it: a small PNG or JPEG whose bytes are what its
//! media type says, with its size read from its own header.
//!
//! Only the header is read, never the image decoded: the registry stores and serves the bytes
//! as they came, so a picture costs it no more than its size. This module must never accept
//! bytes whose magic does not match the declared type, since browsers are told `nosniff`.

use sha2::{Digest, Sha256};

/// The largest picture stored, in bytes: a cropped view around a tag fits well under it.
pub const MAX_PICTURE_BYTES: usize = 256 * 1024;
/// Pictures kept per tag unless the registry is told otherwise: enough to see how a device
/// looked over its recent uses, few enough that a busy switch does not fill the disk.
pub const DEFAULT_PICTURES_PER_TAG: u32 = 20;
/// The longest side a picture may have, in pixels.
pub const MAX_SIDE: u32 = 4096;

/// The two kinds of picture the registry stores.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PictureType {
    Png,
    Jpeg,
}

impl PictureType {
    pub const ALL: [Self; 2] = [Self::Png, Self::Jpeg];

    pub fn media_type(self) -> &'static str {
        match self {
            Self::Png => "image/png",
            Self::Jpeg => "image/jpeg",
        }
    }

    /// The format's name, as a person calls it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Png => "PNG",
            Self::Jpeg => "JPEG",
        }
    }

    /// The type a `Content-Type` header names, parameters ignored.
    pub fn from_content_type(header: &str) -> Option<Self> {
        let essence = header.split(';').next().unwrap_or("").trim().to_ascii_lowercase();
        Self::ALL.into_iter().find(|kind| kind.media_type() == essence)
    }
}

/// A picture whose header was read and found within bounds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Picture {
    pub kind: PictureType,
    pub width: u32,
    pub height: u32,
    /// Hex SHA-256 of the bytes: the idempotency key and the ETag.
    pub sha256: String,
}

/// Why bytes are not a picture the registry stores.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PictureProblem {
    #[error(
        "a picture is at most {MAX_PICTURE_BYTES} bytes (256 KiB); this one has {0}: crop it or compress it harder"
    )]
    TooLarge(usize),
    #[error("the bytes are not a {0}: send PNG bytes as image/png and JPEG bytes as image/jpeg")]
    WrongMagic(&'static str),
    #[error("the {0} header cannot be read: the picture is cut short or damaged")]
    Unreadable(&'static str),
    #[error("a picture is at most {MAX_SIDE} pixels a side; this one is {0}x{1}")]
    TooManyPixels(u32, u32),
}

impl Picture {
    /// Checks `bytes` sent as `kind`: size, magic and dimensions.
    pub fn parse(kind: PictureType, bytes: &[u8]) -> Result<Self, PictureProblem> {
        if bytes.len() > MAX_PICTURE_BYTES {
            return Err(PictureProblem::TooLarge(bytes.len()));
        }
        let (width, height) = match kind {
            PictureType::Png => png_size(bytes)?,
            PictureType::Jpeg => jpeg_size(bytes)?,
        };
        if width == 0 || height == 0 {
            return Err(PictureProblem::Unreadable(kind.name()));
        }
        if width > MAX_SIDE || height > MAX_SIDE {
            return Err(PictureProblem::TooManyPixels(width, height));
        }
        Ok(Self { kind, width, height, sha256: digest(bytes) })
    }
}

/// Hex SHA-256 of `bytes`.
pub fn digest(bytes: &[u8]) -> String {
    hex::encode(Sha256::digest(bytes))
}

const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Width and height from the IHDR chunk, which a PNG must have first.
fn png_size(bytes: &[u8]) -> Result<(u32, u32), PictureProblem> {
    if !bytes.starts_with(PNG_MAGIC) {
        return Err(PictureProblem::WrongMagic("PNG"));
    }
    let header = bytes.get(8..24).ok_or(PictureProblem::Unreadable("PNG"))?;
    if &header[4..8] != b"IHDR" {
        return Err(PictureProblem::Unreadable("PNG"));
    }
    let word = |at: usize| {
        u32::from_be_bytes([header[at], header[at + 1], header[at + 2], header[at + 3]])
    };
    Ok((word(8), word(12)))
}

/// Width and height from the first start-of-frame segment, walking the segments before it.
fn jpeg_size(bytes: &[u8]) -> Result<(u32, u32), PictureProblem> {
    if !bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        return Err(PictureProblem::WrongMagic("JPEG"));
    }
    let unreadable = PictureProblem::Unreadable("JPEG");
    let mut at = 2;
    loop {
        let marker = bytes.get(at..at + 2).ok_or(unreadable.clone())?;
        if marker[0] != 0xFF {
            return Err(unreadable);
        }
        let kind = marker[1];
        // Fill bytes, and markers that stand alone without a length.
        if kind == 0xFF {
            at += 1;
            continue;
        }
        if kind == 0x01 || (0xD0..=0xD7).contains(&kind) {
            at += 2;
            continue;
        }
        let length = bytes.get(at + 2..at + 4).ok_or(unreadable.clone())?;
        let length = usize::from(u16::from_be_bytes([length[0], length[1]]));
        if length < 2 {
            return Err(unreadable);
        }
        // Start of frame: every SOFn but the DHT (C4), JPG (C8) and DAC (CC) markers.
        if (0xC0..=0xCF).contains(&kind) && ![0xC4, 0xC8, 0xCC].contains(&kind) {
            let frame = bytes.get(at + 4..at + 9).ok_or(unreadable)?;
            let height = u32::from(u16::from_be_bytes([frame[1], frame[2]]));
            let width = u32::from(u16::from_be_bytes([frame[3], frame[4]]));
            return Ok((width, height));
        }
        if kind == 0xDA || kind == 0xD9 {
            return Err(unreadable);
        }
        at += 2 + length;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = PNG_MAGIC.to_vec();
        bytes.extend_from_slice(&13u32.to_be_bytes());
        bytes.extend_from_slice(b"IHDR");
        bytes.extend_from_slice(&width.to_be_bytes());
        bytes.extend_from_slice(&height.to_be_bytes());
        bytes.extend_from_slice(&[8, 2, 0, 0, 0, 0, 0, 0, 0]);
        bytes
    }

    /// A JPEG's start: SOI, an APP0 segment, then a baseline frame header.
    fn jpeg(width: u16, height: u16) -> Vec<u8> {
        let mut bytes = vec![0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x06, b'J', b'F', b'I', b'F'];
        bytes.extend_from_slice(&[0xFF, 0xC0, 0x00, 0x11, 8]);
        bytes.extend_from_slice(&height.to_be_bytes());
        bytes.extend_from_slice(&width.to_be_bytes());
        bytes.extend_from_slice(&[3, 1, 0x22, 0, 2, 0x11, 1, 3, 0x11, 1]);
        bytes
    }

    #[test]
    fn sizes_come_from_the_headers() {
        let png = Picture::parse(PictureType::Png, &png(320, 240)).unwrap();
        assert_eq!((png.width, png.height), (320, 240));
        let jpeg = Picture::parse(PictureType::Jpeg, &jpeg(640, 480)).unwrap();
        assert_eq!((jpeg.width, jpeg.height), (640, 480));
        assert_ne!(png.sha256, jpeg.sha256);
    }

    #[test]
    fn the_magic_must_match_the_declared_type() {
        assert_eq!(
            Picture::parse(PictureType::Jpeg, &png(10, 10)),
            Err(PictureProblem::WrongMagic("JPEG"))
        );
        assert_eq!(
            Picture::parse(PictureType::Png, &jpeg(10, 10)),
            Err(PictureProblem::WrongMagic("PNG"))
        );
        assert_eq!(
            Picture::parse(PictureType::Png, b"<svg onload=alert(1)>"),
            Err(PictureProblem::WrongMagic("PNG"))
        );
    }

    #[test]
    fn bounds_hold() {
        assert_eq!(
            Picture::parse(PictureType::Png, &png(5000, 10)),
            Err(PictureProblem::TooManyPixels(5000, 10))
        );
        assert_eq!(
            Picture::parse(PictureType::Png, &png(0, 10)),
            Err(PictureProblem::Unreadable("PNG"))
        );
        let mut big = png(10, 10);
        big.resize(MAX_PICTURE_BYTES + 1, 0);
        assert_eq!(
            Picture::parse(PictureType::Png, &big),
            Err(PictureProblem::TooLarge(MAX_PICTURE_BYTES + 1))
        );
        assert_eq!(
            Picture::parse(PictureType::Jpeg, &jpeg(10, 10)[..12]),
            Err(PictureProblem::Unreadable("JPEG"))
        );
        assert_eq!(
            Picture::parse(PictureType::Png, &png(10, 10)[..20]),
            Err(PictureProblem::Unreadable("PNG"))
        );
    }

    #[test]
    fn content_types_are_read_without_parameters() {
        assert_eq!(PictureType::from_content_type("image/PNG; q=1"), Some(PictureType::Png));
        assert_eq!(PictureType::from_content_type("image/jpeg"), Some(PictureType::Jpeg));
        assert_eq!(PictureType::from_content_type("image/gif"), None);
    }
}
