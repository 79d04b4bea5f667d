//! Round trips of random fields and random binary, and inputs that must never panic.

use proptest::prelude::*;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use super::*;

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
