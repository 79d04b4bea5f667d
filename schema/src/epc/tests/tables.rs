//! The TDS tables, pinned by their structure, and every scheme and partition at its limits.

use super::*;

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
