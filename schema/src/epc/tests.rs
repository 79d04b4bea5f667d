//! Tests of the EPC key: hex parsing, the TDS tables, both URI directions and the error messages.

use proptest::prelude::*;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use super::scheme::{Row, SCHEMES, Scheme, Segment};
use super::{Epc, EpcError};

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

/// (hex, tag URI, pure-identity URI). The first is the worked example of the TDS (Annex E); the
/// SGTIN `0037000` one is the TDT standard's figure example; the rest are the test vectors of
/// GS1 TDT engine implementations and EPC libraries, each cross-checked bit by bit.
const PUBLISHED: &[(&str, &str, &str)] = &[
    (
        "3074257BF7194E4000001A85",
        "urn:epc:tag:sgtin-96:3.0614141.812345.6789",
        "urn:epc:id:sgtin:0614141.812345.6789",
    ),
    (
        "30740242201D8840000FE632",
        "urn:epc:tag:sgtin-96:3.0037000.030241.1041970",
        "urn:epc:id:sgtin:0037000.030241.1041970",
    ),
    (
        "311BA1B300CE0A6A83000000",
        "urn:epc:tag:sscc-96:0.952012.03456789123",
        "urn:epc:id:sscc:952012.03456789123",
    ),
    (
        "3159542C8000000001000000",
        "urn:epc:tag:sscc-96:2.348338.00000000001",
        "urn:epc:id:sscc:348338.00000000001",
    ),
    (
        "3276451FD46072000000162E",
        "urn:epc:tag:sgln-96:3.9521141.12345.5678",
        "urn:epc:id:sgln:9521141.12345.5678",
    ),
    (
        "320661AEBD33A287CEA6443D",
        "urn:epc:tag:sgln-96:0.81830209949.1.583287587901",
        "urn:epc:id:sgln:81830209949.1.583287587901",
    ),
    (
        "32305E30A7466800499602D2",
        "urn:epc:tag:sgln-96:1.12345678.9012.1234567890",
        "urn:epc:id:sgln:12345678.9012.1234567890",
    ),
    (
        "330C75BCD150030000000001",
        "urn:epc:tag:grai-96:0.123456789.012.1",
        "urn:epc:id:grai:123456789.012.1",
    ),
    (
        "33B4257BF40C0E4000000190",
        "urn:epc:tag:grai-96:5.0614141.12345.400",
        "urn:epc:id:grai:0614141.12345.400",
    ),
    (
        "3374257BF4000200000004D2",
        "urn:epc:tag:grai-96:3.0614141.00008.1234",
        "urn:epc:id:grai:0614141.00008.1234",
    ),
    (
        "33403C3C3C3C3C3F0000FFFF",
        "urn:epc:tag:grai-96:2.064677154575..270583005183",
        "urn:epc:id:grai:064677154575..270583005183",
    ),
    (
        "3474257BF40000000000162E",
        "urn:epc:tag:giai-96:3.0614141.5678",
        "urn:epc:id:giai:0614141.5678",
    ),
    (
        "3414257BF400000000BC6038",
        "urn:epc:tag:giai-96:0.0614141.12345400",
        "urn:epc:id:giai:0614141.12345400",
    ),
    ("34344B5A1C00000000000001", "urn:epc:tag:giai-96:1.1234567.1", "urn:epc:id:giai:1234567.1"),
    (
        "350007AB70425D4000000586",
        "urn:epc:tag:gid-96:31415.271828.1414",
        "urn:epc:id:gid:31415.271828.1414",
    ),
];

#[test]
fn epc_published_examples_decode() {
    for &(hex, tag, id) in PUBLISHED {
        let epc = parse(hex);
        assert_eq!(epc.tag_uri().as_deref(), Some(tag), "{hex}");
        assert_eq!(epc.pure_identity_uri().as_deref(), Some(id), "{hex}");
    }
}

#[test]
fn epc_published_examples_encode() {
    for &(hex, tag, _) in PUBLISHED {
        assert_eq!(parse(tag).as_hex(), hex, "{tag}");
    }
}

#[test]
fn epc_tds_worked_example_accessors() {
    let epc = parse("3074257bf7194e4000001a85");
    assert_eq!(epc.as_hex(), "3074257BF7194E4000001A85");
    assert_eq!(epc.scheme(), Some("sgtin-96"));
    assert_eq!(epc.filter(), Some(3));
    let gid = parse("350007AB70425D4000000586");
    assert_eq!(gid.scheme(), Some("gid-96"));
    assert_eq!(gid.filter(), None);
}

#[test]
fn epc_tds_pure_identity_examples_from_tag_uris() {
    // The pure-identity examples of the TDS's EPC URI chapter, written as tag URIs with filter 3.
    let cases = [
        ("urn:epc:tag:sscc-96:3.0614141.1234567890", "urn:epc:id:sscc:0614141.1234567890"),
        ("urn:epc:tag:sgln-96:3.0614141.12345.400", "urn:epc:id:sgln:0614141.12345.400"),
        ("urn:epc:tag:grai-96:3.0614141.12345.400", "urn:epc:id:grai:0614141.12345.400"),
        ("urn:epc:tag:giai-96:3.0614141.12345400", "urn:epc:id:giai:0614141.12345400"),
        ("urn:epc:tag:gid-96:95100000.12345.400", "urn:epc:id:gid:95100000.12345.400"),
    ];
    for (tag, id) in cases {
        let epc = parse(tag);
        assert_eq!(epc.as_hex().len(), 24);
        assert_eq!(epc.tag_uri().as_deref(), Some(tag));
        assert_eq!(epc.pure_identity_uri().as_deref(), Some(id));
    }
}

#[test]
fn epc_project_seed_gids_decode() {
    for n in 1..=5 {
        let epc = parse(&format!("355AB1C6000000{n}000000001"));
        assert_eq!(epc.pure_identity_uri(), Some(format!("urn:epc:id:gid:95100000.{n}.1")));
        assert_eq!(epc.tag_uri(), Some(format!("urn:epc:tag:gid-96:95100000.{n}.1")));
    }
}

/// The TDS tables pinned by their structure: the company-prefix columns are common to all five
/// schemes, and each scheme's prefix and reference always add up to the same bits and digits.
#[test]
fn epc_partition_tables_match_tds_structure() {
    const CP_BITS: [u32; 7] = [40, 37, 34, 30, 27, 24, 20];
    // (scheme, header, prefix+reference bits, prefix+reference digits, bits after them)
    let expected = [
        ("sgtin-96", 0x30, 44, 13, 38),
        ("sscc-96", 0x31, 58, 17, 24),
        ("sgln-96", 0x32, 41, 12, 41),
        ("grai-96", 0x33, 44, 12, 38),
        ("giai-96", 0x34, 82, 25, 0),
    ];
    for (name, header, bits, digits, tail) in expected {
        let scheme = scheme(name);
        assert_eq!(scheme.header, header);
        let tail_bits: u32 = scheme
            .segments
            .iter()
            .map(|segment| match segment {
                Segment::Integer(_, width) | Segment::Zero(width) => *width,
                _ => 0,
            })
            .sum();
        assert_eq!(tail_bits, tail, "{name}");
        assert_eq!(8 + 3 + 3 + bits + tail, 96, "{name}");
        for (partition, row) in scheme.partitions.unwrap().iter().enumerate() {
            assert_eq!(row.cp_bits, CP_BITS[partition], "{name} partition {partition}");
            assert_eq!(row.cp_digits, 12 - partition, "{name} partition {partition}");
            assert_eq!(row.cp_bits + row.ref_bits, bits, "{name} partition {partition}");
            assert_eq!(row.cp_digits + row.ref_digits, digits, "{name} {partition}");
        }
    }
    // Any value typed with a fixed-digit field's digits fits in its bits.
    for scheme in SCHEMES.iter().filter(|s| s.partitions.is_some()) {
        for row in scheme.partitions.unwrap() {
            assert!(10u128.pow(row.cp_digits as u32) <= 1 << row.cp_bits);
            if matches!(scheme.segments[1], Segment::PaddedRef(_)) {
                assert!(10u128.pow(row.ref_digits as u32) <= 1 << row.ref_bits);
            }
        }
    }
    // GIAI's reference is a plain integer: its bits, not its digit count, set its limit.
    for row in scheme("giai-96").partitions.unwrap() {
        assert!(1u128 << row.ref_bits <= 10u128.pow(row.ref_digits as u32));
    }
    let gid = scheme("gid-96");
    assert_eq!(gid.header, 0x35);
    assert!(gid.partitions.is_none());
    let widths: Vec<u32> = gid
        .segments
        .iter()
        .map(|segment| match segment {
            Segment::Integer(_, width) => *width,
            other => panic!("GID-96 has only integers, not {other:?}"),
        })
        .collect();
    assert_eq!(widths, [28, 24, 36]);
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

#[test]
fn epc_every_scheme_and_partition_at_the_limits() {
    for scheme in partitioned() {
        for partition in 0..7 {
            // The largest value each field may hold, then the smallest (all zeros, padded).
            let max = fields(scheme, 1, partition, |width, digits| {
                digits.map_or((1 << width) - 1, |limit| limit - 1)
            });
            check_decodes(scheme, 1, &max);
            let zero = fields(scheme, 6, partition, |_, _| 0);
            check_decodes(scheme, 6, &zero);
            let row = scheme.partitions.unwrap()[partition];
            assert!(zero.uri[0].len() == row.cp_digits && zero.uri[0].bytes().all(|b| b == b'0'));
        }
    }
}

#[test]
fn epc_values_beyond_the_digit_count_do_not_decode() {
    for scheme in partitioned() {
        for partition in 0..7 {
            let row = scheme.partitions.unwrap()[partition];
            // A company prefix one past its digits, where its bits can hold that value.
            let cp_limit = 10u128.pow(row.cp_digits as u32);
            if cp_limit < 1 << row.cp_bits {
                let mut bits = fields(scheme, 0, partition, |_, _| 0).bits;
                bits[3] = (row.cp_bits, cp_limit);
                let epc = parse(&pack(&bits));
                assert_eq!(epc.pure_identity_uri(), None, "{} {partition}", scheme.tag_name);
                assert_eq!(epc.tag_uri(), None);
            }
            // A fixed-digit reference one past its digits (for zero digits: any value but 0).
            if matches!(scheme.segments[1], Segment::PaddedRef(_)) {
                let mut bits = fields(scheme, 0, partition, |_, _| 0).bits;
                bits[4] = (row.ref_bits, 10u128.pow(row.ref_digits as u32));
                let epc = parse(&pack(&bits));
                assert_eq!(epc.pure_identity_uri(), None, "{} {partition}", scheme.tag_name);
            }
        }
    }
}

#[test]
fn epc_every_filter_value() {
    for scheme in partitioned() {
        for filter in 0..8 {
            let f = fields(scheme, filter, 5, |_, _| 7);
            check_decodes(scheme, filter, &f);
        }
        let fields = fields(scheme, 0, 5, |_, _| 7).uri.join(".");
        let eight = format!("urn:epc:tag:{}:8.{fields}", scheme.tag_name);
        assert!(matches!(error(&eight), EpcError::Filter { .. }), "{eight}");
    }
}

#[test]
fn epc_zero_digit_fields() {
    let sgln = parse("urn:epc:tag:sgln-96:3.061414112345..400");
    assert_eq!(sgln.pure_identity_uri().as_deref(), Some("urn:epc:id:sgln:061414112345..400"));
    assert_eq!(
        sgln.as_hex(),
        pack(&[(8, 0x32), (3, 3), (3, 0), (40, 61_414_112_345), (1, 0), (41, 400)])
    );
    let grai = parse("urn:epc:tag:grai-96:0.061414112345..0");
    assert_eq!(grai.pure_identity_uri().as_deref(), Some("urn:epc:id:grai:061414112345..0"));
    // The one location-reference bit and four asset-type bits must then be zero.
    let loc_set = pack(&[(8, 0x32), (3, 3), (3, 0), (40, 1), (1, 1), (41, 400)]);
    assert_eq!(parse(&loc_set).tag_uri(), None);
    let asset_set = pack(&[(8, 0x33), (3, 3), (3, 0), (40, 1), (4, 9), (38, 400)]);
    assert_eq!(parse(&asset_set).tag_uri(), None);
    // A zero-digit field written with a digit is an error that says to leave it empty.
    let message = error("urn:epc:tag:grai-96:3.061414112345.0.400").to_string();
    assert!(message.contains("12-digit company prefix"), "{message}");
    assert!(message.contains("no digits (leave it empty"), "{message}");
}

#[test]
fn epc_sscc_unallocated_bits_must_be_zero() {
    let hex = pack(&[(8, 0x31), (3, 0), (3, 5), (24, 614_141), (34, 1), (24, 1)]);
    assert_eq!(parse(&hex).pure_identity_uri(), None);
}

#[test]
fn epc_partition_seven_is_a_valid_key_without_uri() {
    for scheme in partitioned() {
        let hex = pack(&[(8, scheme.header.into()), (3, 1), (3, 7), (82, 5)]);
        let epc = parse(&hex);
        assert_eq!(epc.as_hex(), hex);
        assert_eq!(epc.pure_identity_uri(), None);
        assert_eq!(epc.tag_uri(), None);
        assert_eq!(epc.scheme(), None);
        assert_eq!(epc.filter(), None);
    }
}

#[test]
fn epc_unknown_header_is_a_valid_key_without_uri() {
    // A Gen2 EPC with a non-GS1 header, and GS1 headers at lengths other than 96 bits.
    for hex in
        ["E20034120000000000001001", "3074257BF7194E4000001A850000", "3074257BF7194E40", "3074"]
    {
        let epc = parse(hex);
        assert_eq!(epc.pure_identity_uri(), None, "{hex}");
        assert_eq!(epc.tag_uri(), None, "{hex}");
        assert_eq!(epc.scheme(), None, "{hex}");
    }
}

#[test]
fn epc_hex_is_trimmed_and_upper_cased() {
    let epc = parse("  e20034120000000000001001\n");
    assert_eq!(epc.as_hex(), "E20034120000000000001001");
    assert_eq!(epc.to_string(), "E20034120000000000001001");
    assert_eq!("e200".parse::<Epc>().unwrap().as_hex(), "E200");
    assert_eq!(parse(&"f".repeat(124)).as_hex(), "F".repeat(124));
}

#[test]
fn epc_tag_uri_prefix_and_scheme_ignore_case() {
    let epc = parse(" URN:EPC:TAG:SGTIN-96:3.0614141.812345.6789 ");
    assert_eq!(epc.as_hex(), "3074257BF7194E4000001A85");
}

#[test]
fn epc_serde_is_a_validated_string() {
    let epc: Epc = serde_json::from_str("\"3074257bf7194e4000001a85\"").unwrap();
    assert_eq!(serde_json::to_string(&epc).unwrap(), "\"3074257BF7194E4000001A85\"");
    let from_uri: Epc =
        serde_json::from_str("\"urn:epc:tag:sgtin-96:3.0614141.812345.6789\"").unwrap();
    assert_eq!(from_uri, epc);
    let e = serde_json::from_str::<Epc>("\"30Z4\"").unwrap_err();
    assert!(e.to_string().contains("'Z' at position 3"), "{e}");
    assert!(serde_json::from_str::<Epc>("42").is_err());
}

#[test]
fn epc_errors_for_hex_name_the_problem() {
    assert_eq!(error(""), EpcError::Empty);
    assert_eq!(error(" \t\n"), EpcError::Empty);
    assert!(error("").to_string().contains("must not be empty"));

    let e = error("30G4");
    assert_eq!(e, EpcError::NotHex { found: 'G', position: 3 });
    let message = e.to_string();
    assert!(message.contains("'G' at position 3 is not a hex digit"), "{message}");
    assert!(error(" 30 74").to_string().contains("' ' at position 3"));
    assert!(error("30é4").to_string().contains("'é' at position 3"));

    for len in [3, 5, 128] {
        let e = error(&"A".repeat(len));
        assert_eq!(e, EpcError::Length(len));
        let message = e.to_string();
        assert!(message.contains(&format!("this one has {len}")), "{message}");
        assert!(message.contains("4 to 124 hex digits"), "{message}");
        assert!(message.contains("multiple of 4"), "{message}");
    }
}

#[test]
fn epc_errors_for_uris_name_the_problem() {
    let cases: &[(&str, &[&str])] = &[
        ("urn:epc:id:sgtin:0614141.812345.6789", &["pure-identity URI", "urn:epc:tag:"]),
        ("urn:epc:raw:96.x3074257BF7194E4000001A85", &["not an EPC tag URI"]),
        ("urn:isbn:0451450523", &["not an EPC tag URI"]),
        (
            "urn:epc:tag:sgtin-198:3.0614141.812345.32a%2Fb",
            &["\"sgtin-198\"", "sgtin-96, sscc-96", "as hex"],
        ),
        ("urn:epc:tag:sgtin-96", &["expected 4", "found 0"]),
        (
            "urn:epc:tag:sgtin-96:3.0614141.812345",
            &["expected 4 dot-separated fields", "item reference", "found 3"],
        ),
        ("urn:epc:tag:gid-96:1.2.3.4", &["gid-96 tag URI", "expected 3", "found 4"]),
        (
            "urn:epc:tag:sgtin-96:9.0614141.812345.6789",
            &["filter value is one digit 0 to 7, not \"9\""],
        ),
        ("urn:epc:tag:sscc-96:03.0614141.1234567890", &["filter value", "\"03\""]),
        (
            "urn:epc:tag:sgtin-96:3.0614141x.812345.6789",
            &["company prefix must be decimal digits", "\"0614141x\""],
        ),
        (
            "urn:epc:tag:sgtin-96:3.0614141234567.8.6789",
            &["company prefix has 6 to 12 digits", "not 13"],
        ),
        ("urn:epc:tag:sgln-96:3.06141.123456.0", &["6 to 12 digits", "not 5"]),
        (
            "urn:epc:tag:sgtin-96:3.0614141.81234.6789",
            &["7-digit company prefix the item reference has exactly 6 digits, not 5"],
        ),
        (
            "urn:epc:tag:sscc-96:3.0614141.123456789",
            &["serial reference has exactly 10 digits, not 9"],
        ),
        (
            "urn:epc:tag:sgln-96:3.061414112345.1.400",
            &["location reference has no digits", "not 1"],
        ),
        (
            "urn:epc:tag:sgtin-96:3.0614141.812345.67a9",
            &["serial must be decimal digits", "\"67a9\""],
        ),
        ("urn:epc:tag:sgtin-96:3.0614141.812345.", &["serial is missing"]),
        (
            "urn:epc:tag:sgtin-96:3.0614141.812345.06789",
            &["serial \"06789\" must not start with 0", "leading zeros"],
        ),
        (
            "urn:epc:tag:sgtin-96:3.0614141.812345.274877906944",
            &["serial 274877906944 is too large", "at most 274877906943", "38 bits"],
        ),
        (
            "urn:epc:tag:sgln-96:3.0614141.12345.2199023255552",
            &["extension 2199023255552 is too large", "2199023255551", "41 bits"],
        ),
        (
            "urn:epc:tag:giai-96:3.061414112345.4398046511104",
            &["individual asset reference", "at most 4398046511103", "42 bits"],
        ),
        (
            "urn:epc:tag:giai-96:3.0614141.99999999999999999999999999",
            &["too large", "at most 288230376151711743"],
        ),
        (
            "urn:epc:tag:gid-96:268435456.1.1",
            &["general manager number 268435456 is too large", "28 bits"],
        ),
        ("urn:epc:tag:gid-96:95100000.16777216.1", &["object class", "at most 16777215"]),
        (
            "urn:epc:tag:gid-96:95100000.1.68719476736",
            &["serial", "at most 68719476735", "36 bits"],
        ),
    ];
    for (input, needles) in cases {
        let message = error(input).to_string();
        for needle in *needles {
            assert!(message.contains(needle), "{input}: {message:?} lacks {needle:?}");
        }
    }
}

#[test]
fn epc_errors_do_not_echo_huge_input() {
    let input = format!("urn:epc:tag:{}:1.2.3", "x".repeat(10_000));
    let message = error(&input).to_string();
    assert!(message.len() < 400, "{message}");
    assert!(message.contains('…'));
}

/// A value below `limit`, often an edge (0 or the largest) since that is where bugs live.
fn pick(rng: &mut StdRng, limit: u128) -> u128 {
    match rng.random_range(0..8) {
        0 => 0,
        1 => limit - 1,
        _ => rng.random_range(0..limit),
    }
}

#[test]
fn epc_random_fields_round_trip_through_tag_uri_and_hex() {
    let mut rng = StdRng::seed_from_u64(0x5EED);
    for _ in 0..4000 {
        let scheme = &SCHEMES[rng.random_range(0..SCHEMES.len())];
        let (hex, tag, id, filter) = if scheme.partitions.is_some() {
            let filter = rng.random_range(0..8u8);
            let partition = rng.random_range(0..7);
            let f = fields(scheme, filter, partition, |width, digits| {
                pick(&mut rng, digits.unwrap_or(1 << width))
            });
            let tag = format!("urn:epc:tag:{}:{filter}.{}", scheme.tag_name, f.uri.join("."));
            let id = format!("urn:epc:id:{}:{}", scheme.id_name, f.uri.join("."));
            (pack(&f.bits), tag, id, Some(filter))
        } else {
            let (manager, class, serial) =
                (pick(&mut rng, 1 << 28), pick(&mut rng, 1 << 24), pick(&mut rng, 1 << 36));
            let hex = pack(&[(8, 0x35), (28, manager), (24, class), (36, serial)]);
            let tail = format!("{manager}.{class}.{serial}");
            (hex, format!("urn:epc:tag:gid-96:{tail}"), format!("urn:epc:id:gid:{tail}"), None)
        };
        let epc = parse(&tag);
        assert_eq!(epc.as_hex(), hex, "{tag}");
        assert_eq!(epc.tag_uri().as_deref(), Some(tag.as_str()), "{hex}");
        assert_eq!(epc.pure_identity_uri().as_deref(), Some(id.as_str()), "{hex}");
        assert_eq!(epc.scheme(), Some(scheme.tag_name));
        assert_eq!(epc.filter(), filter);
    }
}

#[test]
fn epc_random_binary_that_decodes_encodes_back() {
    let mut rng = StdRng::seed_from_u64(96);
    let mut decoded = 0;
    for _ in 0..4000 {
        let header = rng.random_range(0x30..=0x35u128);
        let value = (header << 88) | rng.random_range(0..1u128 << 88);
        let hex = format!("{value:024X}");
        let epc = parse(&hex);
        if let Some(tag) = epc.tag_uri() {
            decoded += 1;
            assert_eq!(parse(&tag).as_hex(), hex, "{tag}");
            assert!(epc.pure_identity_uri().is_some());
        }
    }
    // Most random bits are valid (all GID, 7 in 8 partitions); a low count means a decode bug.
    assert!(decoded > 1500, "only {decoded} decoded");
}

#[test]
fn epc_random_hex_round_trips_upper_case() {
    const DIGITS: &[u8] = b"0123456789abcdefABCDEF";
    let mut rng = StdRng::seed_from_u64(124);
    for _ in 0..4000 {
        let len = 4 * rng.random_range(1..=31);
        let hex: String =
            (0..len).map(|_| DIGITS[rng.random_range(0..DIGITS.len())] as char).collect();
        let epc = parse(&hex);
        assert_eq!(epc.as_hex(), hex.to_ascii_uppercase());
        assert_eq!(parse(epc.as_hex()), epc);
    }
}

proptest! {
    #[test]
    fn epc_parse_never_panics(input in any::<String>()) {
        if let Ok(epc) = Epc::parse(&input) {
            prop_assert_eq!(parse(epc.as_hex()), epc);
        }
    }

    #[test]
    fn epc_parse_of_uri_like_input_never_panics(
        input in "(urn|URN):(epc|EPC):(tag|id|raw):(sgtin|sscc|sgln|grai|giai|gid|sgtin-96|sscc-96|sgln-96|grai-96|giai-96|gid-96|x)?:?[0-9.a-z%:]{0,60}"
    ) {
        if let Ok(epc) = Epc::parse(&input) {
            prop_assert_eq!(epc.as_hex().len(), 24);
            let tag = epc.tag_uri();
            prop_assert!(tag.is_some());
            prop_assert_eq!(parse(&tag.unwrap()), epc);
        }
    }

    #[test]
    fn epc_any_96_bit_value_with_a_known_header_never_panics(
        header in 0x30u128..=0x35,
        rest in 0u128..(1 << 88),
    ) {
        let epc = parse(&format!("{:024X}", (header << 88) | rest));
        if let Some(tag) = epc.tag_uri() {
            prop_assert_eq!(parse(&tag), epc);
        }
    }
}
