//! The six 96-bit EPC binary encodings the registry turns into URIs (SGTIN-96, SSCC-96, SGLN-96,
//! GRAI-96, GIAI-96, GID-96), laid out as the GS1 EPC Tag Data Standard's coding and partition
//! tables give them, with the decoder (hex → URIs) and the tag-URI encoder (URI → hex).
//!
//! It is long because half of it is the standard's tables, transcribed so as to be read against
//! them, and the decoder and encoder walk those same rows field by field.

use super::{EpcError, excerpt};

/// One row of a TDS partition table: how the bits after the partition value are split between
/// the GS1 company prefix and the reference that follows it, and how many digits each has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Row {
    pub cp_bits: u32,
    pub cp_digits: usize,
    pub ref_bits: u32,
    pub ref_digits: usize,
}

const fn row(cp_bits: u32, cp_digits: usize, ref_bits: u32, ref_digits: usize) -> Row {
    Row { cp_bits, cp_digits, ref_bits, ref_digits }
}

/// SGTIN partition table; the reference is the indicator digit followed by the item reference.
pub(super) const SGTIN_PARTITIONS: [Row; 7] = [
    row(40, 12, 4, 1),
    row(37, 11, 7, 2),
    row(34, 10, 10, 3),
    row(30, 9, 14, 4),
    row(27, 8, 17, 5),
    row(24, 7, 20, 6),
    row(20, 6, 24, 7),
];

/// SSCC partition table; the reference is the extension digit followed by the serial reference.
pub(super) const SSCC_PARTITIONS: [Row; 7] = [
    row(40, 12, 18, 5),
    row(37, 11, 21, 6),
    row(34, 10, 24, 7),
    row(30, 9, 28, 8),
    row(27, 8, 31, 9),
    row(24, 7, 34, 10),
    row(20, 6, 38, 11),
];

/// SGLN partition table; with a 12-digit company prefix the location reference has no digits.
pub(super) const SGLN_PARTITIONS: [Row; 7] = [
    row(40, 12, 1, 0),
    row(37, 11, 4, 1),
    row(34, 10, 7, 2),
    row(30, 9, 11, 3),
    row(27, 8, 14, 4),
    row(24, 7, 17, 5),
    row(20, 6, 21, 6),
];

/// GRAI partition table; with a 12-digit company prefix the asset type has no digits.
pub(super) const GRAI_PARTITIONS: [Row; 7] = [
    row(40, 12, 4, 0),
    row(37, 11, 7, 1),
    row(34, 10, 10, 2),
    row(30, 9, 14, 3),
    row(27, 8, 17, 4),
    row(24, 7, 20, 5),
    row(20, 6, 24, 6),
];

/// GIAI partition table; the reference digit count is a maximum (it is coded as an integer).
pub(super) const GIAI_PARTITIONS: [Row; 7] = [
    row(40, 12, 42, 13),
    row(37, 11, 45, 14),
    row(34, 10, 48, 15),
    row(30, 9, 52, 16),
    row(27, 8, 55, 17),
    row(24, 7, 58, 18),
    row(20, 6, 62, 19),
];

/// One segment of a coding table after the header (and, when present, filter and partition).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Segment {
    /// The GS1 company prefix, zero-padded to the partition row's digit count.
    CompanyPrefix,
    /// The reference after the prefix, zero-padded to the row's digit count, which may be 0.
    PaddedRef(&'static str),
    /// The reference after the prefix as a plain integer in the row's bit width (GIAI).
    IntegerRef(&'static str),
    /// A plain integer of a fixed width: no leading zeros, any value the bits hold.
    Integer(&'static str, u32),
    /// Bits the standard leaves unallocated; a valid encoding has them all zero.
    Zero(u32),
}

/// A coding table: the header value, URI names and segments of one 96-bit scheme.
#[derive(Debug)]
pub(super) struct Scheme {
    pub header: u8,
    /// The name in tag URIs, e.g. `sgtin-96`.
    pub tag_name: &'static str,
    /// The name in pure-identity URIs, e.g. `sgtin`.
    pub id_name: &'static str,
    /// Present when filter and partition values follow the header.
    pub partitions: Option<&'static [Row; 7]>,
    pub segments: &'static [Segment],
    /// How the fields of the tag URI read, for error messages.
    pub layout: &'static str,
}

impl Scheme {
    /// The number of dot-separated fields in this scheme's tag URI.
    fn uri_fields(&self) -> usize {
        let filter = usize::from(self.partitions.is_some());
        filter + self.segments.iter().filter(|segment| !matches!(segment, Segment::Zero(_))).count()
    }
}

pub(super) const SCHEMES: [Scheme; 6] = [
    Scheme {
        header: 0x30,
        tag_name: "sgtin-96",
        id_name: "sgtin",
        partitions: Some(&SGTIN_PARTITIONS),
        segments: &[
            Segment::CompanyPrefix,
            Segment::PaddedRef("item reference"),
            Segment::Integer("serial", 38),
        ],
        layout: "filter.company prefix.item reference.serial",
    },
    Scheme {
        header: 0x31,
        tag_name: "sscc-96",
        id_name: "sscc",
        partitions: Some(&SSCC_PARTITIONS),
        segments: &[
            Segment::CompanyPrefix,
            Segment::PaddedRef("serial reference"),
            Segment::Zero(24),
        ],
        layout: "filter.company prefix.serial reference",
    },
    Scheme {
        header: 0x32,
        tag_name: "sgln-96",
        id_name: "sgln",
        partitions: Some(&SGLN_PARTITIONS),
        segments: &[
            Segment::CompanyPrefix,
            Segment::PaddedRef("location reference"),
            Segment::Integer("extension", 41),
        ],
        layout: "filter.company prefix.location reference.extension",
    },
    Scheme {
        header: 0x33,
        tag_name: "grai-96",
        id_name: "grai",
        partitions: Some(&GRAI_PARTITIONS),
        segments: &[
            Segment::CompanyPrefix,
            Segment::PaddedRef("asset type"),
            Segment::Integer("serial", 38),
        ],
        layout: "filter.company prefix.asset type.serial",
    },
    Scheme {
        header: 0x34,
        tag_name: "giai-96",
        id_name: "giai",
        partitions: Some(&GIAI_PARTITIONS),
        segments: &[Segment::CompanyPrefix, Segment::IntegerRef("individual asset reference")],
        layout: "filter.company prefix.individual asset reference",
    },
    Scheme {
        header: 0x35,
        tag_name: "gid-96",
        id_name: "gid",
        partitions: None,
        segments: &[
            Segment::Integer("general manager number", 28),
            Segment::Integer("object class", 24),
            Segment::Integer("serial", 36),
        ],
        layout: "general manager number.object class.serial",
    },
];

/// A 96-bit EPC that is a valid encoding of one of [`SCHEMES`].
#[derive(Debug)]
pub(super) struct Decoded {
    pub scheme: &'static Scheme,
    pub filter: Option<u8>,
    /// The URI fields after the filter, already formatted.
    fields: Vec<String>,
}

impl Decoded {
    pub fn pure_identity_uri(&self) -> String {
        format!("urn:epc:id:{}:{}", self.scheme.id_name, self.fields.join("."))
    }

    pub fn tag_uri(&self) -> String {
        let fields = self.fields.join(".");
        match self.filter {
            Some(filter) => format!("urn:epc:tag:{}:{filter}.{fields}", self.scheme.tag_name),
            None => format!("urn:epc:tag:{}:{fields}", self.scheme.tag_name),
        }
    }
}

/// Reads fields most significant bit first from a 96-bit value.
struct BitReader {
    value: u128,
    left: u32,
}

impl BitReader {
    fn take(&mut self, width: u32) -> u64 {
        self.left -= width;
        // No field is wider than 62 bits, so the masked value fits in u64.
        ((self.value >> self.left) & ((1u128 << width) - 1)) as u64
    }
}

/// Decodes upper-case hex to its scheme and URI fields, or `None` when it is not a valid
/// 96-bit encoding of one of the six schemes.
pub(super) fn decode(hex: &str) -> Option<Decoded> {
    if hex.len() != 24 {
        return None;
    }
    let mut bits = BitReader { value: u128::from_str_radix(hex, 16).ok()?, left: 96 };
    let header = bits.take(8);
    let scheme = SCHEMES.iter().find(|s| u64::from(s.header) == header)?;
    let (filter, row) = match scheme.partitions {
        Some(table) => {
            let filter = bits.take(3) as u8;
            // Partition 7 is not in any table: the bits are not a valid encoding.
            let row = *table.get(bits.take(3) as usize)?;
            (Some(filter), Some(row))
        }
        None => (None, None),
    };
    let mut fields = Vec::with_capacity(scheme.segments.len());
    for segment in scheme.segments {
        match *segment {
            Segment::CompanyPrefix => {
                let row = row?;
                fields.push(padded(bits.take(row.cp_bits), row.cp_digits)?);
            }
            Segment::PaddedRef(_) => {
                let row = row?;
                fields.push(padded(bits.take(row.ref_bits), row.ref_digits)?);
            }
            Segment::IntegerRef(_) => {
                // Every value of the row's bits has at most its digits, so any value is valid.
                fields.push(bits.take(row?.ref_bits).to_string());
            }
            Segment::Integer(_, width) => fields.push(bits.take(width).to_string()),
            Segment::Zero(width) => {
                if bits.take(width) != 0 {
                    return None;
                }
            }
        }
    }
    debug_assert_eq!(bits.left, 0, "{} segments must fill 96 bits", scheme.tag_name);
    Some(Decoded { scheme, filter, fields })
}

/// `Some` when `value` has at most `digits` decimal digits (0 digits: only the value 0).
fn fits_digits(value: u64, digits: usize) -> Option<()> {
    let limit = 10u64.checked_pow(u32::try_from(digits).ok()?)?;
    (value < limit).then_some(())
}

/// `value` zero-padded to exactly `digits` digits, or `None` when it needs more.
fn padded(value: u64, digits: usize) -> Option<String> {
    fits_digits(value, digits)?;
    // `{:0width$}` still prints "0" at width 0, but a zero-digit field is empty in the URI.
    Some(if digits == 0 { String::new() } else { format!("{value:0digits$}") })
}

/// Encodes the body of a tag URI (what follows `urn:epc:tag:`) to 24 upper-case hex digits.
pub(super) fn encode_tag_uri(body: &str) -> Result<String, EpcError> {
    let (name, fields) = body.split_once(':').unwrap_or((body, ""));
    let scheme = SCHEMES
        .iter()
        .find(|s| s.tag_name.eq_ignore_ascii_case(name))
        .ok_or_else(|| EpcError::UnknownScheme(excerpt(name)))?;
    let fields: Vec<&str> =
        if fields.is_empty() { Vec::new() } else { fields.split('.').collect() };
    if fields.len() != scheme.uri_fields() {
        return Err(EpcError::FieldCount {
            scheme: scheme.tag_name,
            expected: scheme.uri_fields(),
            found: fields.len(),
            layout: scheme.layout,
        });
    }
    let mut fields = fields.into_iter();
    let mut next = || fields.next().unwrap_or_default();
    let mut out = Packer::default();
    out.push(8, u64::from(scheme.header));

    // Filter, then the partition the company prefix's length picks, precede every segment.
    let mut row = None;
    let mut prefix = 0;
    if let Some(table) = scheme.partitions {
        let filter = next();
        let [digit @ b'0'..=b'7'] = *filter.as_bytes() else {
            return Err(EpcError::Filter { scheme: scheme.tag_name, found: excerpt(filter) });
        };
        let text = next();
        digits_only(scheme, "company prefix", text)?;
        let partition = table
            .iter()
            .position(|r| r.cp_digits == text.len())
            .ok_or(EpcError::CompanyPrefixDigits { scheme: scheme.tag_name, found: text.len() })?;
        out.push(3, u64::from(digit - b'0'));
        out.push(3, partition as u64);
        row = Some(table[partition]);
        prefix = decimal(text);
    }
    let row = || row.expect("only partitioned schemes have prefix-relative segments");

    for segment in scheme.segments {
        match *segment {
            Segment::CompanyPrefix => out.push(row().cp_bits, prefix),
            Segment::PaddedRef(field) => {
                let (row, text) = (row(), next());
                digits_only(scheme, field, text)?;
                if text.len() != row.ref_digits {
                    return Err(EpcError::ReferenceDigits {
                        scheme: scheme.tag_name,
                        field,
                        company_prefix_digits: row.cp_digits,
                        expected: row.ref_digits,
                        found: text.len(),
                    });
                }
                out.push(row.ref_bits, decimal(text));
            }
            Segment::IntegerRef(field) => {
                let width = row().ref_bits;
                out.push(width, integer(scheme, field, next(), width)?);
            }
            Segment::Integer(field, width) => {
                out.push(width, integer(scheme, field, next(), width)?);
            }
            Segment::Zero(width) => out.push(width, 0),
        }
    }
    debug_assert_eq!(out.len, 96, "{} segments must fill 96 bits", scheme.tag_name);
    Ok(format!("{:024X}", out.value))
}

/// Appends fields most significant bit first.
#[derive(Default)]
struct Packer {
    value: u128,
    len: u32,
}

impl Packer {
    fn push(&mut self, width: u32, value: u64) {
        debug_assert!(u128::from(value) < 1u128 << width, "{value} overflows {width} bits");
        self.value = (self.value << width) | u128::from(value);
        self.len += width;
    }
}

fn digits_only(scheme: &Scheme, field: &'static str, text: &str) -> Result<(), EpcError> {
    if text.bytes().all(|b| b.is_ascii_digit()) {
        Ok(())
    } else {
        Err(EpcError::NotDigits { scheme: scheme.tag_name, field, found: excerpt(text) })
    }
}

/// The value of a field already checked to be at most 12 digits (it always fits in u64).
fn decimal(text: &str) -> u64 {
    text.bytes().fold(0, |acc, b| acc * 10 + u64::from(b - b'0'))
}

/// Parses a field coded as a plain integer: digits, no leading zeros, below `2^width`.
fn integer(scheme: &Scheme, field: &'static str, text: &str, width: u32) -> Result<u64, EpcError> {
    if text.is_empty() {
        return Err(EpcError::NotDigits { scheme: scheme.tag_name, field, found: String::new() });
    }
    digits_only(scheme, field, text)?;
    if text.len() > 1 && text.starts_with('0') {
        return Err(EpcError::LeadingZeros {
            scheme: scheme.tag_name,
            field,
            found: excerpt(text),
        });
    }
    let max = (1u64 << width) - 1;
    let value = text
        .bytes()
        .try_fold(0u64, |acc, b| acc.checked_mul(10)?.checked_add(u64::from(b - b'0')))
        .filter(|value| *value <= max);
    value.ok_or_else(|| EpcError::OutOfRange {
        scheme: scheme.tag_name,
        field,
        found: excerpt(text),
        max,
        bits: width,
    })
}
