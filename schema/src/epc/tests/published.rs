//! The published examples: the TDS's worked example, the TDT figure, GS1 engines' and EPC
//! libraries' test vectors, and the project's seed tags.

use super::*;

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
