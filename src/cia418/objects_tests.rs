//! The battery module's whole dictionary (application objects here, the
//! communication objects of the device core, the PDO objects) as an SDO
//! server sees it.

use super::*;
use crate::cia418::{
    BatteryModule, BatteryModuleConfig, BatteryParameterValue, BatteryType, DeviceType,
};
use crate::device::{Dictionary, Identity};
use crate::od::ObjectDictionary;
use crate::NodeId;

type Od = Dictionary<BatteryDictionary, 3, 3>;

fn module_od(node: u8, name: &'static str, f: impl FnOnce(&mut BatteryModuleConfig)) -> Od {
    let mut config = BatteryModuleConfig::new(NodeId::new(node).unwrap());
    config.device_name = name;
    f(&mut config);
    BatteryModule::new(config).dictionary().clone()
}

fn od() -> Od {
    module_od(1, "Battery module", |_| {})
}

fn read(od: &mut Od, index: u16, sub: u8) -> Result<std::vec::Vec<u8>, AbortCode> {
    let len = od.info(index, sub)?.len;
    let mut buf = std::vec![0u8; len];
    let n = od.read(index, sub, 0, &mut buf)?;
    assert_eq!(n, len, "{index:04X}h:{sub} read length");
    Ok(buf)
}

fn write(od: &mut Od, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
    let info = od.info(index, sub)?;
    if !info.access.is_writable() {
        // What the SDO server checks before writing; the dictionary checks
        // it too, when the value is complete.
        od.write(index, sub, 0, data)?;
        assert_eq!(
            od.finish_write(index, sub, data.len()),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
        return Err(AbortCode::WriteOfReadOnlyObject);
    }
    od.write(index, sub, 0, data)?;
    od.finish_write(index, sub, data.len())
}

/// CiA 418 v1.0.1, 7.3.1-7.3.18 (the application objects' type and access),
/// row by row: (index, sub, access, length, mappable).
const TABLE: &[(u16, u8, Access, usize, bool)] = &[
    (0x6000, 0, Access::ReadOnly, 1, true),
    (0x6001, 0, Access::ReadWrite, 1, true),
    (0x6010, 0, Access::ReadOnly, 2, true),
    (0x6020, 0, Access::ReadOnly, 1, false),
    (0x6020, 1, Access::ReadOnly, 1, false),
    (0x6020, 2, Access::ReadOnly, 2, false),
    (0x6020, 3, Access::ReadOnly, 2, false),
    (0x6020, 4, Access::ReadOnly, 2, false),
    (0x6030, 0, Access::ReadOnly, 1, false),
    (0x6030, 1, Access::ReadOnly, 4, false),
    (0x6031, 0, Access::ReadOnly, 1, false),
    (0x6031, 1, Access::ReadOnly, 4, false),
    (0x6040, 0, Access::ReadOnly, 1, false),
    (0x6040, 1, Access::ReadOnly, 4, false),
    (0x6041, 0, Access::ReadOnly, 1, false),
    (0x6041, 1, Access::ReadOnly, 4, false),
    (0x6050, 0, Access::ReadOnly, 4, false),
    (0x6051, 0, Access::ReadOnly, 2, false),
    (0x6052, 0, Access::ReadWrite, 2, true),
    (0x6053, 0, Access::ReadWrite, 2, false),
    (0x6054, 0, Access::ReadOnly, 1, false),
    (0x6054, 1, Access::ReadWrite, 2, false),
    (0x6054, 2, Access::ReadWrite, 2, false),
    (0x6060, 0, Access::ReadOnly, 4, true),
    (0x6070, 0, Access::ReadOnly, 2, true),
    (0x6080, 0, Access::ReadWrite, 1, true),
    (0x6081, 0, Access::ReadOnly, 1, true),
    (0x6090, 0, Access::ReadOnly, 1, false),
    (0x1000, 0, Access::Const, 4, false),
    (0x1001, 0, Access::ReadOnly, 1, false),
    (0x1017, 0, Access::ReadWrite, 2, false),
    (0x1018, 0, Access::ReadOnly, 1, false),
    (0x1018, 1, Access::ReadOnly, 4, false),
    (0x1018, 4, Access::ReadOnly, 4, false),
    (0x1200, 0, Access::ReadOnly, 1, false),
    (0x1200, 1, Access::ReadOnly, 4, false),
    (0x1200, 2, Access::ReadOnly, 4, false),
];

#[test]
fn every_object_has_its_access_length_and_mapping() {
    let mut od = od();
    for &(index, sub, access, len, mappable) in TABLE {
        let info = od.info(index, sub).unwrap();
        assert_eq!(info.access, access, "{index:04X}h:{sub}");
        assert_eq!(info.len, len, "{index:04X}h:{sub}");
        assert_eq!(info.pdo_mappable, mappable, "{index:04X}h:{sub}");
        assert_eq!(read(&mut od, index, sub).unwrap().len(), len);
        // Write back a value of the right length: rw accepted, ro refused.
        let value = std::vec![0x01; len];
        let got = write(&mut od, index, sub, &value);
        if access.is_writable() {
            assert_eq!(got, Ok(()), "{index:04X}h:{sub}");
            assert_eq!(read(&mut od, index, sub).unwrap(), value);
        } else {
            assert_eq!(got, Err(AbortCode::WriteOfReadOnlyObject));
        }
    }
}

/// The indexes the application dictionary serves are the objects of CiA
/// 418 v1.0.1, 7.3.1-7.3.18, each once and in index order: the 6000h-6FFFh
/// ones of the literal table above.
#[test]
fn the_served_indexes_are_the_profiles_objects() {
    let mut want: std::vec::Vec<u16> = TABLE
        .iter()
        .map(|&(index, ..)| index)
        .filter(|index| (0x6000..=0x6FFF).contains(index))
        .collect();
    want.dedup();
    assert_eq!(want.len(), 18);
    assert_eq!(BATTERY_OBJECT_INDEXES.as_slice(), want.as_slice());
}

#[test]
fn every_table_index_is_served() {
    for index in BATTERY_OBJECT_INDEXES {
        assert!(od().info(index, 0).is_ok(), "{index:04X}h");
    }
}

#[test]
fn writable_objects_refuse_wrong_lengths() {
    let mut od = od();
    for &(index, sub, access, len, _) in TABLE {
        if !access.is_writable() {
            continue;
        }
        let long = std::vec![0; len + 1];
        assert_eq!(
            write(&mut od, index, sub, &long),
            Err(AbortCode::DataTypeLengthTooHigh),
            "{index:04X}h:{sub}"
        );
        let short = std::vec![0; len - 1];
        assert_eq!(
            write(&mut od, index, sub, &short),
            Err(AbortCode::DataTypeLengthTooLow),
            "{index:04X}h:{sub}"
        );
    }
}

#[test]
fn missing_objects_and_sub_indexes() {
    let od = od();
    assert_eq!(od.info(0x6002, 0), Err(AbortCode::ObjectDoesNotExist));
    assert_eq!(od.info(0x2000, 0), Err(AbortCode::ObjectDoesNotExist));
    for (index, sub) in [
        (0x6000, 1),
        (0x6020, 5),
        (0x6054, 3),
        (0x1018, 5),
        (0x1200, 3),
        (0x1008, 1),
        (0x6030, 2), // beyond the element count
        (0x6041, 6),
    ] {
        assert_eq!(
            od.info(index, sub),
            Err(AbortCode::SubIndexDoesNotExist),
            "{index:04X}h:{sub}"
        );
    }
}

#[test]
fn communication_object_values() {
    let mut od = module_od(5, "BMS-418", |c| {
        c.device_type = DeviceType::cia418(DeviceType::TPDO_2ND);
        c.identity = Identity {
            vendor_id: 0x0000_0123,
            product_code: 0x418,
            revision_number: 0x0001_0002,
            serial_number: 0xDEAD_BEEF,
        };
    });
    assert_eq!(read(&mut od, 0x1000, 0).unwrap(), [0xA2, 0x01, 0x04, 0x00]);
    assert_eq!(read(&mut od, 0x1001, 0).unwrap(), [0]);
    assert_eq!(read(&mut od, 0x1008, 0).unwrap(), b"BMS-418");
    assert_eq!(od.info(0x1008, 0).unwrap().access, Access::Const);
    assert_eq!(read(&mut od, 0x1017, 0).unwrap(), [0xE8, 0x03]);
    assert_eq!(read(&mut od, 0x1018, 0).unwrap(), [4]);
    assert_eq!(read(&mut od, 0x1018, 1).unwrap(), [0x23, 0x01, 0, 0]);
    assert_eq!(read(&mut od, 0x1018, 2).unwrap(), [0x18, 0x04, 0, 0]);
    assert_eq!(read(&mut od, 0x1018, 3).unwrap(), [0x02, 0, 0x01, 0]);
    assert_eq!(read(&mut od, 0x1018, 4).unwrap(), [0xEF, 0xBE, 0xAD, 0xDE]);
    assert_eq!(read(&mut od, 0x1200, 0).unwrap(), [2]);
    assert_eq!(read(&mut od, 0x1200, 1).unwrap(), [0x05, 0x06, 0, 0]);
    assert_eq!(read(&mut od, 0x1200, 2).unwrap(), [0x85, 0x05, 0, 0]);
}

#[test]
fn device_name_reads_at_offsets() {
    let mut od = od();
    let mut buf = [0u8; 7];
    assert_eq!(od.read(0x1008, 0, 0, &mut buf), Ok(7));
    assert_eq!(&buf, b"Battery");
    assert_eq!(od.read(0x1008, 0, 7, &mut buf), Ok(7));
    assert_eq!(&buf, b" module");
    assert_eq!(od.read(0x1008, 0, 14, &mut buf), Ok(0));
    assert_eq!(od.read(0x1008, 0, usize::MAX, &mut buf), Ok(0));
}

#[test]
fn packed_string_arrays() {
    let mut od = od();
    od.inner
        .app
        .set_text(PackedStringObject::BatterySerialNumber, "BATTERY")
        .unwrap();
    assert_eq!(read(&mut od, 0x6030, 0).unwrap(), [2]);
    assert_eq!(
        read(&mut od, 0x6030, 1).unwrap(),
        0x5454_4142u32.to_le_bytes()
    );
    assert_eq!(
        read(&mut od, 0x6030, 2).unwrap(),
        0x0059_5245u32.to_le_bytes()
    );
    assert_eq!(od.info(0x6030, 3), Err(AbortCode::SubIndexDoesNotExist));
    assert_eq!(
        od.inner
            .app
            .packed_string(PackedStringObject::BatterySerialNumber)
            .unwrap()
            .text()
            .as_str(),
        "BATTERY"
    );
    // 20 characters: five elements.
    od.inner
        .app
        .set_text(PackedStringObject::VehicleId, "ABCDEFGHIJKLMNOPQRST")
        .unwrap();
    assert_eq!(read(&mut od, 0x6041, 0).unwrap(), [5]);
    assert_eq!(read(&mut od, 0x6041, 5).unwrap(), *b"QRST");
    // A packed string with padding elements.
    let p = PackedString::encode_with_count(PackedStringObject::BatteryId, "AB", 3).unwrap();
    od.inner.app.set_packed_string(&p);
    assert_eq!(read(&mut od, 0x6031, 0).unwrap(), [3]);
    assert_eq!(read(&mut od, 0x6031, 1).unwrap(), [b'A', b'B', 0, 0]);
    assert_eq!(read(&mut od, 0x6031, 3).unwrap(), [0, 0, 0, 0]);
    // Empty by default: one zero element.
    assert_eq!(read(&mut od, 0x6040, 0).unwrap(), [1]);
    assert_eq!(read(&mut od, 0x6040, 1).unwrap(), [0, 0, 0, 0]);
    assert!(od
        .inner
        .app
        .set_text(PackedStringObject::BatterySerialNumber, "ELEVEN CHAR")
        .is_err());
}

#[test]
fn application_values_are_little_endian() {
    let mut od = od();
    od.inner.app.temperature = Temperature::from_raw(-80);
    od.inner.app.battery_voltage = BatteryVoltage::from_raw(51_200);
    od.inner
        .app
        .battery_parameters
        .set(BatteryParameterValue::BatteryType(BatteryType::from_u8(
            0x10,
        )));
    od.inner.app.battery_parameters.ah_capacity = 600;
    assert_eq!(read(&mut od, 0x6010, 0).unwrap(), [0xB0, 0xFF]);
    assert_eq!(read(&mut od, 0x6060, 0).unwrap(), [0x00, 0xC8, 0, 0]);
    assert_eq!(read(&mut od, 0x6020, 0).unwrap(), [4]);
    assert_eq!(read(&mut od, 0x6020, 1).unwrap(), [0x10]);
    assert_eq!(read(&mut od, 0x6020, 2).unwrap(), [0x58, 0x02]);
    assert_eq!(read(&mut od, 0x6070, 0).unwrap(), [0xFF, 0xFF]);
    assert_eq!(read(&mut od, 0x6080, 0).unwrap(), [0xFF]);
    assert_eq!(read(&mut od, 0x6081, 0).unwrap(), [0xFF]);
    assert_eq!(read(&mut od, 0x6054, 0).unwrap(), [2]);
}

#[test]
fn value_checks() {
    let mut od = od();
    assert_eq!(write(&mut od, 0x6080, 0, &[100]), Ok(()));
    assert_eq!(write(&mut od, 0x6080, 0, &[0xFF]), Ok(()));
    assert_eq!(
        write(&mut od, 0x6080, 0, &[101]),
        Err(AbortCode::ValueTooHigh)
    );
    assert_eq!(od.inner.app.charger_state_of_charge, StateOfCharge::INVALID);
    assert_eq!(
        write(&mut od, 0x6054, 1, &1440u16.to_le_bytes()),
        Err(AbortCode::ValueTooHigh)
    );
    assert_eq!(write(&mut od, 0x6054, 1, &1439u16.to_le_bytes()), Ok(()));
    assert_eq!(od.inner.app.date_of_last_equalization.minutes, 1439);
    assert_eq!(
        write(&mut od, 0x6054, 0, &[2]),
        Err(AbortCode::WriteOfReadOnlyObject)
    );
    assert_eq!(write(&mut od, 0x1017, 0, &[0xF4, 0x01]), Ok(()));
    assert_eq!(od.inner.comm.heartbeat_ms, 500);
    assert_eq!(write(&mut od, 0x6001, 0, &[0x81]), Ok(()));
    assert_eq!(od.inner.app.charger_status.bits(), 0x81);
}

#[test]
fn segmented_write_in_pieces_and_abort() {
    let mut od = od();
    od.write(0x6052, 0, 0, &[0x10]).unwrap();
    od.write(0x6052, 0, 1, &[0x02]).unwrap();
    od.finish_write(0x6052, 0, 2).unwrap();
    assert_eq!(od.inner.app.ah_returned_during_last_charge.raw(), 0x0210);
    // Out-of-order offset.
    assert_eq!(
        od.write(0x6052, 0, 3, &[0]),
        Err(AbortCode::DataTypeLengthTooHigh)
    );
    crate::od::fixture::assert_aborted_write_changes_nothing(&mut od, 0x6052, 0, 2);
    assert_eq!(od.inner.app.ah_returned_during_last_charge.raw(), 0x0210);
}

#[test]
fn hostile_reads_and_writes_never_panic() {
    let mut od = od();
    let mut buf = [0u8; 8];
    for index in [0x1000u16, 0x1008, 0x1018, 0x6030, 0x6054, 0xFFFF, 0] {
        for sub in [0u8, 1, 4, 5, 0xFF] {
            let _ = od.read(index, sub, usize::MAX, &mut buf);
            let _ = od.read(index, sub, 3, &mut []);
            let _ = od.write(index, sub, usize::MAX, &[1, 2, 3]);
            let _ = od.write(index, sub, 0, &[0; 9]);
            let _ = od.finish_write(index, sub, usize::MAX);
        }
    }
}

/// The module has 3 RPDOs and 3 TPDOs (CiA 418 v1.0.1, 6.2.5): with every
/// optional PDO of the device type on, 1402h/1602h/1802h/1A02h are served
/// and the fourth PDO's objects do not exist (CiA 301: PDO objects exist
/// for the PDOs a device has), for info, read and write alike; a module
/// without the optional PDOs lacks 1401h-1402h / 1801h-1802h the same way.
#[test]
fn the_fourth_pdo_does_not_exist() {
    let all =
        DeviceType::RPDO_2ND | DeviceType::RPDO_3RD | DeviceType::TPDO_2ND | DeviceType::TPDO_3RD;
    let mut od = module_od(1, "BMS", |c| c.device_type = DeviceType::cia418(all));
    for index in [0x1402u16, 0x1602, 0x1802, 0x1A02] {
        assert!(read(&mut od, index, 0).is_ok(), "{index:04X}h present");
        assert!(read(&mut od, index, 1).is_ok(), "{index:04X}h:1 present");
    }
    let mut buf = [0u8; 4];
    for index in [0x1403u16, 0x1603, 0x1803, 0x1A03] {
        for sub in [0u8, 1, 2, 8] {
            let gone = Err(AbortCode::ObjectDoesNotExist);
            assert_eq!(od.info(index, sub).map(|_| ()), gone, "{index:04X}h:{sub}");
            assert_eq!(od.read(index, sub, 0, &mut buf).map(|_| ()), gone);
            assert_eq!(od.write(index, sub, 0, &[0, 0, 0, 0x80]), gone);
            assert_eq!(od.finish_write(index, sub, 4), gone);
        }
    }
    // 1404h and up are not PDO objects at all: the application's (absent).
    assert_eq!(
        od.info(0x1404, 0).map(|_| ()),
        Err(AbortCode::ObjectDoesNotExist)
    );
    let mut od = self::od();
    assert!(read(&mut od, 0x1400, 1).is_ok() && read(&mut od, 0x1A00, 1).is_ok());
    for index in [0x1401u16, 0x1602, 0x1801, 0x1A02] {
        assert_eq!(
            od.info(index, 0).map(|_| ()),
            Err(AbortCode::ObjectDoesNotExist)
        );
    }
}
