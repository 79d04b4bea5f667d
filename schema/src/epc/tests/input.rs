//! What parsing accepts of a person's input (case, spaces, serde) and the errors it names.

use super::*;

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
