//! The generic default-PDO row: COB-ID, presence, mapping values and the
//! lookups, on a small table of its own (the profiles' tables are tested
//! row by row in their modules).

use super::*;
use PdoDirection::{Receive, Transmit};

use crate::cob_id::test_node as n;

const TABLE: [DefaultPdo; 3] = [
    DefaultPdo {
        direction: Transmit,
        number: PdoNumber::P0,
        communication_index: 0x1800,
        mapping_index: 0x1A00,
        cob_id_base: 0x8000_0180,
        transmission_type: 255,
        event_timer_ms: 200,
        entries: &[(0x6010, 0, 16), (0x6000, 0, 8)],
        enabled_by: None,
    },
    DefaultPdo {
        direction: Receive,
        number: PdoNumber::P1,
        communication_index: 0x1401,
        mapping_index: 0x1601,
        cob_id_base: 0x300,
        transmission_type: 255,
        event_timer_ms: 0,
        entries: &[(0x6001, 0, 8), (0x6052, 0, 16)],
        enabled_by: Some(1 << 16 | 1 << 3),
    },
    DefaultPdo {
        direction: Receive,
        number: PdoNumber::P3,
        communication_index: 0x1403,
        mapping_index: 0x1603,
        cob_id_base: 0x500,
        transmission_type: 255,
        event_timer_ms: 0,
        entries: &[],
        enabled_by: None,
    },
];

#[test]
fn cob_id_keeps_the_flags() {
    assert_eq!(TABLE[0].cob_id(n(1)), 0x8000_0181);
    assert_eq!(TABLE[0].cob_id(n(127)), 0x8000_01FF);
    assert_eq!(TABLE[1].cob_id(n(10)), 0x30A);
}

#[test]
fn presence_needs_every_bit() {
    assert!(TABLE[0].is_present(0u32));
    assert!(!TABLE[1].is_present(1u32 << 16));
    assert!(TABLE[1].is_present(1u32 << 16 | 1 << 3 | 0x1A2));
}

#[test]
fn mapping_values_and_bits() {
    assert!(TABLE[0]
        .mapping_values()
        .eq([0x6010_0010, 0x6000_0008].into_iter()));
    assert_eq!(TABLE[0].total_bits(), 24);
    assert_eq!(TABLE[2].total_bits(), 0);
    assert_eq!(
        TABLE[1].mapping().unwrap().entries(),
        &[
            MappingEntry::new(0x6001, 0, 8),
            MappingEntry::new(0x6052, 0, 16)
        ]
    );
    // No entries: no published mapping.
    assert_eq!(TABLE[2].mapping(), None);
}

#[test]
fn lookups() {
    assert_eq!(
        find_default(&TABLE, Receive, PdoNumber::P1),
        Some(&TABLE[1])
    );
    assert_eq!(find_default(&TABLE, Receive, PdoNumber::P0), None);
    assert_eq!(find_default(&[], Transmit, PdoNumber::P0), None);
    assert_eq!(
        default_mapping(&TABLE, Transmit, PdoNumber::P0).map(|m| m.total_bits()),
        Some(24)
    );
    assert_eq!(default_mapping(&TABLE, Receive, PdoNumber::P3), None);
    assert_eq!(default_mapping(&TABLE, Transmit, PdoNumber::P2), None);
}
