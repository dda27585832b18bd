//! Table tests for the CiA 418 module: object indexes and default PDOs.

use super::*;
use crate::cob_id::PdoNumber;

/// CiA 418 v1.0.1, 7.3.1-7.3.18: the index of every application object, row
/// by row.
#[test]
fn object_indexes() {
    let rows: [(u16, u16); 18] = [
        (BATTERY_STATUS, 0x6000),
        (CHARGER_STATUS, 0x6001),
        (TEMPERATURE, 0x6010),
        (BATTERY_PARAMETERS, 0x6020),
        (BATTERY_SERIAL_NUMBER, 0x6030),
        (BATTERY_ID, 0x6031),
        (VEHICLE_SERIAL_NUMBER, 0x6040),
        (VEHICLE_ID, 0x6041),
        (CUMULATIVE_TOTAL_AH_CHARGE, 0x6050),
        (AH_EXPENDED_SINCE_LAST_CHARGE, 0x6051),
        (AH_RETURNED_DURING_LAST_CHARGE, 0x6052),
        (AH_SINCE_LAST_EQUALIZATION, 0x6053),
        (DATE_OF_LAST_EQUALIZATION, 0x6054),
        (BATTERY_VOLTAGE, 0x6060),
        (CHARGE_CURRENT_REQUESTED, 0x6070),
        (CHARGER_STATE_OF_CHARGE, 0x6080),
        (BATTERY_STATE_OF_CHARGE, 0x6081),
        (WATER_LEVEL_STATUS, 0x6090),
    ];
    for (constant, literal) in rows {
        assert_eq!(constant, literal);
    }
    assert_eq!(DEVICE_TYPE, 0x1000);
    assert_eq!(ERROR_REGISTER, 0x1001);
    assert_eq!(BATTERY_PAR_DATA_TYPE, 0x0080);
}

use crate::cob_id::test_node as node;

type Row = (
    PdoDirection,
    PdoNumber,
    u16,
    u16,
    u32,
    u16,
    &'static [(u16, u8, u8)],
    Option<u32>,
);

/// CiA 418 v1.0.1, 6.2.3-6.2.8: the default PDOs of the battery module, row
/// by row, with literal values (COB-ID for node 1, then node 127).
#[test]
fn default_pdo_rows() {
    #[rustfmt::skip]
    let rows: [Row; 6] = [
        (PdoDirection::Receive, PdoNumber::P0, 0x1400, 0x1600, 0x201, 0, &[(0x6001, 0, 8)], None),
        (PdoDirection::Receive, PdoNumber::P1, 0x1401, 0x1601, 0x301, 0, &[(0x6001, 0, 8), (0x6052, 0, 16)], Some(1 << 16)),
        (PdoDirection::Receive, PdoNumber::P2, 0x1402, 0x1602, 0x401, 0, &[(0x6001, 0, 8), (0x6052, 0, 16), (0x6080, 0, 8)], Some(1 << 17)),
        (PdoDirection::Transmit, PdoNumber::P0, 0x1800, 0x1A00, 0x8000_0181, 200, &[(0x6010, 0, 16), (0x6000, 0, 8)], None),
        (PdoDirection::Transmit, PdoNumber::P1, 0x1801, 0x1A01, 0x8000_0281, 200, &[(0x6010, 0, 16), (0x6000, 0, 8), (0x6060, 0, 32)], Some(1 << 18)),
        (PdoDirection::Transmit, PdoNumber::P2, 0x1802, 0x1A02, 0x8000_0381, 200, &[(0x6070, 0, 16), (0x6081, 0, 8)], Some(1 << 19)),
    ];
    for (pdo, (dir, number, comm, mapping, cob1, timer, entries, bit)) in
        DEFAULT_PDOS.iter().zip(rows)
    {
        assert_eq!(pdo.direction, dir);
        assert_eq!(pdo.number, number);
        assert_eq!(pdo.communication_index, comm);
        assert_eq!(pdo.mapping_index, mapping);
        assert_eq!(pdo.cob_id(node(1)), cob1);
        assert_eq!(pdo.cob_id(node(127)), cob1 + 126);
        assert_eq!(pdo.transmission_type, 255);
        assert_eq!(pdo.event_timer_ms, timer);
        assert_eq!(pdo.entries, entries);
        assert_eq!(pdo.enabled_by, bit);
        assert!(pdo.total_bits() <= 64);
        // Comm. and mapping indexes follow the PDO number.
        let (comm_base, map_base) = match dir {
            PdoDirection::Receive => (0x1400, 0x1600),
            PdoDirection::Transmit => (0x1800, 0x1A00),
        };
        assert_eq!(comm, comm_base + u16::from(number.raw()));
        assert_eq!(mapping, map_base + u16::from(number.raw()));
        // The device type with only this PDO's bit sets the PDO present and
        // the PDO sets of DeviceType agree.
        let dt = DeviceType::cia418(bit.unwrap_or(0));
        assert!(pdo.is_present(dt));
        let set = match dir {
            PdoDirection::Receive => dt.rpdos(),
            PdoDirection::Transmit => dt.tpdos(),
        };
        assert!(set.contains(number));
        if bit.is_some() {
            assert!(!pdo.is_present(DeviceType::cia418(0)));
        }
    }
}

#[test]
fn default_pdo_mapping_values() {
    let values: [&[u32]; 6] = [
        &[0x6001_0008],
        &[0x6001_0008, 0x6052_0010],
        &[0x6001_0008, 0x6052_0010, 0x6080_0008],
        &[0x6010_0010, 0x6000_0008],
        &[0x6010_0010, 0x6000_0008, 0x6060_0020],
        &[0x6070_0010, 0x6081_0008],
    ];
    for (pdo, expected) in DEFAULT_PDOS.iter().zip(values) {
        assert!(pdo.mapping_values().eq(expected.iter().copied()));
    }
    assert_eq!(DEFAULT_PDOS[4].total_bits(), 56);
}

#[test]
fn battery_defaults_from_the_cia418_table() {
    let m = battery_default_mapping(PdoDirection::Transmit, PdoNumber::P1).unwrap();
    assert_eq!(
        m.entries(),
        &[
            crate::pdo::MappingEntry::new(0x6010, 0, 16),
            crate::pdo::MappingEntry::new(0x6000, 0, 8),
            crate::pdo::MappingEntry::new(0x6060, 0, 32),
        ]
    );
    let m = battery_default_mapping(PdoDirection::Receive, PdoNumber::P2).unwrap();
    assert_eq!(m.total_bits(), 32);
}
