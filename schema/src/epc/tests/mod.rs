//! Tests of the EPC key, one file for each way of checking it: the published examples, the TDS
//! tables at their limits, a person's input and the errors it gets, and random round trips.
//! Here are the helpers they share.

use super::scheme::{Row, SCHEMES, Scheme, Segment};
use super::{Epc, EpcError};

mod input;
mod published;
mod random;
mod tables;

/// Packs `(width, value)` fields most significant bit first into 96-bit upper-case hex; written
/// apart from the module's packer so the two check each other.
fn pack(fields: &[(u32, u128)]) -> String {
    let mut value = 0u128;
    let mut len = 0;
    for &(width, field) in fields {
        assert!(field < 1u128 << width, "{field} does not fit in {width} bits");
        value = (value << width) | field;
        len += width;
    }
    assert_eq!(len, 96);
    format!("{value:024X}")
}

fn parse(input: &str) -> Epc {
    Epc::parse(input).unwrap_or_else(|e| panic!("{input:?} should parse: {e}"))
}

fn error(input: &str) -> EpcError {
    match Epc::parse(input) {
        Ok(epc) => panic!("{input:?} should not parse, got {epc}"),
        Err(e) => e,
    }
}

fn scheme(name: &str) -> &'static Scheme {
    SCHEMES.iter().find(|s| s.tag_name == name).unwrap()
}

/// One value per segment, in bits and as the URI spells it.
struct Fields {
    bits: Vec<(u32, u128)>,
    uri: Vec<String>,
}

/// Builds the hex and URI fields of a partitioned scheme; `value` chooses each segment's value
/// from (its width in bits, its exclusive digit limit, or `None` for a plain integer).
fn fields(
    scheme: &Scheme,
    filter: u8,
    partition: usize,
    mut value: impl FnMut(u32, Option<u128>) -> u128,
) -> Fields {
    let row: Row = scheme.partitions.unwrap()[partition];
    let mut out = Fields {
        bits: vec![(8, scheme.header.into()), (3, filter.into()), (3, partition as u128)],
        uri: Vec::new(),
    };
    for segment in scheme.segments {
        let (width, v, text) = match *segment {
            Segment::CompanyPrefix => {
                let v = value(row.cp_bits, Some(10u128.pow(row.cp_digits as u32)));
                (row.cp_bits, v, format!("{v:0w$}", w = row.cp_digits))
            }
            Segment::PaddedRef(_) => {
                let v = value(row.ref_bits, Some(10u128.pow(row.ref_digits as u32)));
                let text = match row.ref_digits {
                    0 => String::new(),
                    w => format!("{v:0w$}"),
                };
                (row.ref_bits, v, text)
            }
            Segment::IntegerRef(_) => {
                let v = value(row.ref_bits, None);
                (row.ref_bits, v, v.to_string())
            }
            Segment::Integer(_, width) => {
                let v = value(width, None);
                (width, v, v.to_string())
            }
            Segment::Zero(width) => {
                out.bits.push((width, 0));
                continue;
            }
        };
        out.bits.push((width, v));
        out.uri.push(text);
    }
    out
}

fn partitioned() -> impl Iterator<Item = &'static Scheme> {
    SCHEMES.iter().filter(|s| s.partitions.is_some())
}

fn check_decodes(scheme: &Scheme, filter: u8, f: &Fields) {
    let hex = pack(&f.bits);
    let tag = format!("urn:epc:tag:{}:{filter}.{}", scheme.tag_name, f.uri.join("."));
    let id = format!("urn:epc:id:{}:{}", scheme.id_name, f.uri.join("."));
    let epc = parse(&hex);
    assert_eq!(epc.tag_uri().as_deref(), Some(tag.as_str()), "{hex}");
    assert_eq!(epc.pure_identity_uri().as_deref(), Some(id.as_str()), "{hex}");
    assert_eq!(epc.filter(), Some(filter));
    assert_eq!(parse(&tag).as_hex(), hex, "{tag}");
}
