//! Every row of the Delta-Q charger's default PDO table against literals
//! from "Delta-Q IC Series CANopen interface specification rev 2.0":
//! the default COB-IDs (section 4.3.2), the pairing table and transmit
//! periods (section 4.5.5), TPDO 3 (section 4.6.1) and the EDS default
//! mappings.

use super::*;
use crate::cia418::BATTERY_MODULE_CATALOGUE;
use crate::deltaq::{index, BatteryVoltageLegacy, ChargingCurrent, ExtendedChargeStatus};
use crate::emcy::ErrorCode;
use crate::pdo::catalogue_test_support::mapping;
use crate::pdo::{MappingEntry, UnpackError};
use std::vec::Vec;

use crate::cob_id::test_node as n;

/// (direction, number, comm, mapping, COB-ID of node 0x0A, period, entries
/// as Unsigned32, paired comm index)
type Row = (
    PdoDirection,
    u8,
    u16,
    u16,
    u16,
    Option<u16>,
    Option<&'static [u32]>,
    u16,
);

#[rustfmt::skip]
const DELTAQ_DEFAULT_PDO_ROWS: [Row; 8] = [
    (Transmit, 0, 0x1800, 0x1A00, 0x18A, Some(200), Some(&[0x6001_0008]), 0x1400),
    (Transmit, 1, 0x1801, 0x1A01, 0x28A, Some(200), Some(&[0x6001_0008, 0x6052_0010]), 0x1401),
    (Transmit, 2, 0x1802, 0x1A02, 0x38A, Some(200), Some(&[0x6001_0008, 0x6052_0010, 0x6080_0008]), 0x1402),
    (Transmit, 3, 0x1803, 0x1A03, 0x48A, Some(1000), Some(&[0x2002_0010, 0x2100_0010, 0x2006_0010]), 0x1403),
    (Receive, 0, 0x1400, 0x1600, 0x20A, None, Some(&[0x6010_0010, 0x6000_0008]), 0x1800),
    (Receive, 1, 0x1401, 0x1601, 0x30A, None, Some(&[0x6010_0010, 0x6000_0008, 0x6060_0020]), 0x1801),
    (Receive, 2, 0x1402, 0x1602, 0x40A, None, Some(&[0x6070_0010, 0x6081_0008]), 0x1802),
    // RPDO 3: mapping not published.
    (Receive, 3, 0x1403, 0x1603, 0x50A, None, None, 0x1803),
];

#[test]
fn every_charger_row_matches_the_specification() {
    assert_eq!(CHARGER_DEFAULT_PDOS.len(), DELTAQ_DEFAULT_PDO_ROWS.len());
    for (row, want) in CHARGER_DEFAULT_PDOS.iter().zip(DELTAQ_DEFAULT_PDO_ROWS) {
        let (dir, num, comm, map, cob, period, entries, paired) = want;
        let ctx = format!("{dir:?} {num}");
        assert_eq!(row.direction, dir, "{ctx}");
        assert_eq!(row.number.raw(), num, "{ctx}");
        assert_eq!(row.communication_index, comm, "{ctx}");
        assert_eq!(row.mapping_index, map, "{ctx}");
        assert_eq!(row.cob_id(n(0x0A)), u32::from(cob), "{ctx}");
        assert_eq!(row.event_timer_ms, period.unwrap_or(0), "{ctx}");
        assert_eq!(row.transmission_type, 255, "{ctx}");
        assert_eq!(row.enabled_by, None, "{ctx}");
        let got: std::vec::Vec<u32> = row.mapping_values().collect();
        assert_eq!(got.as_slice(), entries.unwrap_or(&[]), "{ctx}");
        let (paired_direction, paired_comm) = paired_module_pdo(row);
        assert_eq!(paired_comm, paired, "{ctx}");
        // The paired module PDO runs the other way.
        assert_ne!(paired_direction, row.direction, "{ctx}");
        // Lookup by direction and number finds the same row.
        assert_eq!(charger_default_pdo(dir, row.number), row, "{ctx}");
        let mapping = charger_default_mapping(dir, row.number);
        assert_eq!(
            mapping.map(|m| m
                .entries()
                .iter()
                .map(|e| e.to_u32())
                .collect::<std::vec::Vec<_>>()),
            entries.map(<[u32]>::to_vec),
            "{ctx}"
        );
    }
}

#[test]
fn charger_cob_ids_for_the_battery_node_and_the_capture() {
    let p = |d, k| charger_default_pdo(d, PdoNumber::new(k).unwrap());
    assert_eq!(p(Transmit, 0).cob_id(n(1)), 0x181);
    assert_eq!(p(Transmit, 3).cob_id(n(1)), 0x481);
    assert_eq!(p(Receive, 0).cob_id(n(1)), 0x201);
    assert_eq!(p(Receive, 3).cob_id(n(127)), 0x57F);
}

#[test]
fn charger_mappings_mirror_the_battery_module() {
    // The charger's TPDO n carries what the module's RPDO n expects, and
    // its RPDO n what the module's TPDO n sends (n = 0..2).
    for k in 0..3 {
        let k = PdoNumber::new(k).unwrap();
        assert_eq!(
            charger_default_mapping(Transmit, k),
            battery_default_mapping(Receive, k)
        );
        assert_eq!(
            charger_default_mapping(Receive, k),
            battery_default_mapping(Transmit, k)
        );
    }
    assert_eq!(battery_default_mapping(Transmit, PdoNumber::P3), None);
    assert_eq!(battery_default_mapping(Receive, PdoNumber::P3), None);
}

#[test]
fn defaults_by_cob_id() {
    let (c, b) = (n(10), n(1));
    let tpdo3 = default_mapping_for_cob_id(0x48A, c, b).unwrap();
    assert_eq!(tpdo3.0, CHARGER_CATALOGUE);
    assert_eq!(tpdo3.1.total_bits(), 48);
    let battery = default_mapping_for_cob_id(0x181, c, b).unwrap();
    assert_eq!(battery.0, BATTERY_MODULE_CATALOGUE);
    assert_eq!(battery.1.entries()[0], MappingEntry::new(0x6010, 0, 16));
    assert_eq!(default_mapping_for_cob_id(0x50A, c, b), None); // RPDO 3
    assert_eq!(default_mapping_for_cob_id(0x481, c, b), None); // no CiA 418 PDO 3
    assert_eq!(default_mapping_for_cob_id(0x70A, c, b), None); // heartbeat
    assert_eq!(default_mapping_for_cob_id(0x182, c, b), None); // other node
    assert_eq!(default_mapping_for_cob_id(0xFFFF, c, b), None);
}

/// Delta-Q charger TPDO 3: 2002h/16 charging current (Q8 A), 2100h/16
/// battery voltage legacy (Q10 V: the 2100h scale erratum, see
/// [`BatteryVoltageLegacy`]), 2006h/16 extended charge
/// status. Bytes from the capture's `18A#7413454E70000000`, read through
/// the catalogue's mapping (its row is checked against the specification
/// above).
#[test]
fn deltaq_tpdo3() {
    let m = charger_default_mapping(Transmit, PdoNumber::P3).unwrap();
    let data = [0x74, 0x13, 0x45, 0x4E, 0x70, 0x00];
    let u = m.unpack(&data).unwrap();
    assert!(!u.longer_than_mapping());
    let raw16 = |i| u16::try_from(u.raw(i).unwrap()).unwrap();
    let current = ChargingCurrent::from_raw(raw16(0)).unwrap();
    assert_eq!(current.milliamps(), 19_453); // 0x1374 / 256 A
    let volts = BatteryVoltageLegacy::from_raw(raw16(1)).unwrap();
    assert_eq!(volts.raw(), 0x4E45);
    assert_eq!(volts.millivolts(), 19_567); // 0x4E45 / 1024 V = 19.567...
    let status = ExtendedChargeStatus::from_u16(raw16(2));
    assert_eq!(status.to_u16(), 0x0070);
    assert_eq!(
        m.pack_raw(&[0x1374, 0x4E45, 0x0070]).unwrap().as_slice(),
        data
    );
    let entries: Vec<_> = u.iter().map(|(e, raw)| (e.index, raw)).collect();
    assert_eq!(
        entries,
        [(0x2002, 0x1374), (0x2100, 0x4E45), (0x2006, 0x0070)]
    );

    // The whole 8-byte frame: decoded, flagged 8220h.
    let frame = [0x74, 0x13, 0x45, 0x4E, 0x70, 0x00, 0x00, 0x00];
    let long = m.unpack(&frame).unwrap();
    assert_eq!(long.raws(), u.raws());
    assert!(long.longer_than_mapping());
    assert_eq!(long.emcy_code(), Some(ErrorCode::PDO_LENGTH_EXCEEDED));
    assert_eq!(long.emcy_code(), Some(ErrorCode(0x8220)));

    // Cut short: not processed, 8210h.
    for n in 0..6 {
        let e = m.unpack(&data[..n]).unwrap_err();
        assert_eq!(e, UnpackError::TooShort { need: 6, got: n });
        assert_eq!(e.emcy_code(), ErrorCode(0x8210));
    }
}

#[test]
fn deltaq_padding_object() {
    // 2002h/16, 2FFAh:01/8 padding, 2006h/16: the status is read after the
    // padding byte.
    let m = mapping(&[
        (index::CHARGING_CURRENT, 0, 16),
        (index::PADDING, 1, 8),
        (index::EXTENDED_CHARGE_STATUS, 0, 16),
    ]);
    assert_eq!(m.byte_len(), 5);
    let u = m.unpack(&[0x74, 0x13, 0x00, 0x70, 0x00]).unwrap();
    assert_eq!(u.raws(), [0x1374, 0, 0x0070]);
    let p = m.pack_raw(&[0x1374, 0, 0x0070]).unwrap();
    assert_eq!(p.as_slice(), [0x74, 0x13, 0x00, 0x70, 0x00]);
}
