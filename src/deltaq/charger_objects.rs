//! The Delta-Q charger's application objects, the area's one table
//! ([`DELTAQ_OBJECTS`]) and the struct holding their values
//! ([`ChargerObjects`]), declared together once: the CiA 418 objects a CiA
//! 419 charger shares with the battery module (6000h-6081h), the Delta-Q
//! manufacturer objects (Delta-Q IC Series CANopen interface specification
//! rev 2.0, section 5: 2002h, 2006h, 2008h, 2060h, 2100h, 2101h, 2200h,
//! 2241h, 2271h, 2276h, 4201h, and the 2FFAh padding objects its PDO
//! mappings use), and the two objects of the charge control the documents
//! do not name (ours: 2250h Ah target, 2251h elapsed time; see
//! [`charge`](super::charge)). The crate's fixed-word dictionary
//! ([`FixedDictionary`]) serves them by SDO; the charger's EDS and
//! [`CHARGER_CATALOGUE`](super::CHARGER_CATALOGUE) are derived from the
//! same rows. Fixed storage, no allocation. The communication objects
//! (1000h-1FFFh) are the device core's ([`crate::device`]).
//!
//! NMT reset node sets the writable objects (what the battery module's
//! TPDOs and an SDO client write: the parameters) back to their values at
//! boot ([`CHARGER_PARAMETERS_RESTORED`]); the read-only ones are the
//! charger's own readings and state and keep the value the application
//! last set (a boot-time value restored would be published until its next
//! update).

use crate::cia418::{
    AH_RETURNED_DURING_LAST_CHARGE, BATTERY_STATE_OF_CHARGE, BATTERY_STATUS, BATTERY_VOLTAGE,
    CHARGER_STATE_OF_CHARGE, CHARGER_STATUS, CHARGE_CURRENT_REQUESTED, CIA418_OBJECTS, TEMPERATURE,
};
use crate::od::Access::{self, Const, ReadOnly as Ro, ReadWrite as Rw};
use crate::od::DataType::{self, Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use crate::od::{Address, FixedDictionary, Interpretation, Marker, ObjectRow, ObjectType, Unit};

use super::charge::{AH_TARGET, ELAPSED_TIME};
use super::index;
use super::{
    ALGORITHM_REQUEST_FORMAT, DERATE_REASONS_FLAGS, DISPLAYED_ERROR_FORMAT,
    EXTENDED_CHARGE_STATUS_FLAGS, EXTERNAL_OVERRIDE_FLAGS,
};

const A: Option<Unit> = Some(Unit::Ampere);
const V: Option<Unit> = Some(Unit::Volt);
const AH: Option<Unit> = Some(Unit::AmpereHour);

/// The charger's row of a CiA 418 object it shares with the battery
/// module (CiA 419 uses them for the values the two exchange): the CiA 418
/// names, type and reading ([`CIA418_OBJECTS`]) with the charger's access,
/// PDO-mappable. A row whose object CiA 418 lacks would have an empty name
/// (a test checks every row has one).
const fn shared(index: u16, access: Access) -> ObjectRow {
    let mut rows = CIA418_OBJECTS;
    while let [row, rest @ ..] = rows {
        if row.address.index == index && row.address.sub == 0 {
            let mut row = *row;
            row.access = access;
            row.mappable = true;
            return row;
        }
        rows = rest;
    }
    ObjectRow::var(index, "", U8, access)
}

/// A Delta-Q manufacturer object of the charger (Delta-Q IC Series
/// CANopen interface specification rev 2.0, section 5), named `name` as
/// Delta-Q's EDS spells it: PDO-mappable, like every entry of the table
/// but 2FFAh sub 0.
const fn delta_q(index: u16, name: &'static str, data_type: DataType, access: Access) -> ObjectRow {
    ObjectRow::var(index, name, data_type, access).mappable()
}

/// All ones of the row's size (FFh, FFFFh, FFFF_FFFFh).
const fn all_ones(row: &ObjectRow) -> u32 {
    match row.size() {
        1 => 0xFF,
        2 => 0xFFFF,
        _ => u32::MAX,
    }
}

/// `row` (a scaled reading) with all ones of its size read as "no value",
/// Delta-Q's marker for a reading or request that is not set.
const fn no_value(row: ObjectRow) -> ObjectRow {
    let ones = all_ones(&row);
    row.marked(Marker::NoValue(ones as u64), None)
}

/// `row` with "no value" (all ones) as its marker and its power-on value:
/// not set until the charger measures it or the bus writes it.
const fn unset(row: ObjectRow) -> ObjectRow {
    let ones = all_ones(&row);
    no_value(row.default(ones))
}

crate::fixed_objects! {
    /// The charger's object values. Fields are the application's to read
    /// and write; SDO access goes through [`FixedDictionary`] with the
    /// access rights of each object's row in [`DELTAQ_OBJECTS`]
    /// ([`ChargerDictionary`]).
    pub struct ChargerObjects;
    /// The Delta-Q IC Series charger's objects, the area's one table: the
    /// CiA 418 objects it shares with the battery module (with the
    /// charger's access and its reading of 6052h: Q3 Ah like CiA 418, but
    /// 0xFFFF is "no value"), the Delta-Q manufacturer objects (names as
    /// Delta-Q's own EDS spells them), the 2FFAh padding objects and the
    /// charge control's 2250h and 2251h (ours). Every entry is
    /// PDO-mappable but 2FFAh sub 0; 0xFFFF (0xFFFF_FFFF for 32 bits) is
    /// "no value".
    pub const DELTAQ_OBJECTS;
    /// What NMT reset node restores of [`ChargerObjects`]: its writable
    /// objects (2FFAh stores nothing), as they were at boot. The read-only
    /// objects are the charger's own readings and state, not parameters
    /// (CiA 301 7.3.2.2.1: reset node restores the parameters of the
    /// profile areas): they keep what the application last set, so no
    /// stale boot-time value is published until its next update.
    pub const CHARGER_PARAMETERS_RESTORED;
    /// The values of [`CHARGER_PARAMETERS_RESTORED`] kept at boot, their
    /// bytes one after the other.
    ///
    /// ```
    /// use canopen_codec::deltaq::ChargerObjects;
    /// use canopen_codec::device::PowerOnValues;
    /// use canopen_codec::od::FixedDictionary;
    /// let mut od = FixedDictionary::new(ChargerObjects::new());
    /// let at_boot = od.snapshot();
    /// od.battery_soc = 80; // written by the battery module's TPDO
    /// od.ac_voltage = 230 * 16; // measured
    /// od.restore(&at_boot); // reset node
    /// assert_eq!((od.battery_soc, od.ac_voltage), (0xFF, 230 * 16));
    /// ```
    pub type POWER_ON = ChargerPowerOnValues;
    fields {
        /// 6000h battery status (written by the BMS).
        battery_status: u8 = shared(BATTERY_STATUS, Rw),
        /// 6001h charger status (bit 0: able to charge).
        charger_status: u8 = shared(CHARGER_STATUS, Ro),
        /// 6010h battery temperature (0.125 degC).
        temperature: i16 = shared(TEMPERATURE, Rw),
        /// 6052h Ah returned (Delta-Q: Q3 Ah, FFFFh no value).
        ah_returned: u16 = unset(shared(AH_RETURNED_DURING_LAST_CHARGE, Rw)),
        /// 6060h battery voltage (1/1024 V).
        battery_voltage: u32 = shared(BATTERY_VOLTAGE, Rw),
        /// 6070h charge current requested (1/16 A).
        current_requested: u16 = shared(CHARGE_CURRENT_REQUESTED, Rw).default(0xFFFF),
        /// 6080h charger state of charge (%; FFh invalid).
        charger_soc: u8 = shared(CHARGER_STATE_OF_CHARGE, Ro).default(0xFF),
        /// 6081h battery state of charge (%; FFh invalid).
        battery_soc: u8 = shared(BATTERY_STATE_OF_CHARGE, Rw).default(0xFF),
        /// 2002h charging current (Q8 A; 0 at power-on).
        charging_current: u16 =
            no_value(delta_q(index::CHARGING_CURRENT, "Charging Current", U16, Rw)
                .short("charging current").scaled(8, A)),
        /// 2006h extended charge status.
        extended_status: u16 =
            delta_q(index::EXTENDED_CHARGE_STATUS, "Extended Charge Status", U16, Ro)
                .short("extended charge status")
                .reading(Interpretation::Flags(&EXTENDED_CHARGE_STATUS_FLAGS)),
        /// 2060h current displayed error (a 1003h-style entry; 0 none).
        displayed_error: u32 =
            delta_q(index::DISPLAYED_ERROR, "Current Displayed Error/Fault", U32, Ro)
                .short("displayed error")
                .reading(Interpretation::Formatted(&DISPLAYED_ERROR_FORMAT)),
        /// 2100h battery voltage, legacy (Q10 V).
        battery_voltage_q10: u16 =
            unset(delta_q(index::BATTERY_VOLTAGE_LEGACY, "Battery Voltage UINT16", U16, Ro)
                .short("battery voltage (legacy)").scaled(10, V)),
        /// 2101h battery voltage (Q8 V).
        battery_voltage_q8: u16 =
            unset(delta_q(index::BATTERY_VOLTAGE, "Battery Voltage Q8.8", U16, Rw)
                .short("battery voltage").scaled(8, V)),
        /// 2200h AC voltage (Q4 V).
        ac_voltage: u16 =
            unset(delta_q(index::AC_VOLTAGE, "AC Voltage", U16, Ro)
                .short("AC voltage").scaled(4, V)),
        /// 2241h active algorithm request (FFFFFFFFh none, its format says so).
        algorithm_request: u32 =
            unset(delta_q(index::ALGORITHM_REQUEST, "Active Algorithm Request", U32, Rw)
                .short("algorithm request")
                .reading(Interpretation::Formatted(&ALGORITHM_REQUEST_FORMAT))),
        /// 2271h voltage request (Q10 V, FFFFFFFFh none).
        voltage_request: u32 = unset(delta_q(index::VOLTAGE_REQUEST, "Voltage Request", U32, Rw)
            .short("voltage request").scaled(10, V)),
        /// 2276h voltage request (Q8 V, FFFFh none).
        voltage_request_q8: u16 =
            unset(delta_q(index::VOLTAGE_REQUEST_16, "Voltage Request U16 Q8", U16, Rw)
                .short("voltage request").scaled(8, V)),
        /// 4201h external override.
        external_override: u8 = delta_q(index::EXTERNAL_OVERRIDE, "External Override", U8, Rw)
            .short("external override").reading(Interpretation::Flags(&EXTERNAL_OVERRIDE_FLAGS)),
        /// 2008h derate reasons.
        derate_reasons: u8 = delta_q(index::DERATE_REASONS, "Derate Reasons", U8, Ro)
            .short("derate reasons").reading(Interpretation::Flags(&DERATE_REASONS_FLAGS)),
        /// 2250h Ah target (ours, Q3 Ah, FFFFh none; see
        /// [`charge::AH_TARGET`](super::charge::AH_TARGET)).
        ah_target: u16 =
            unset(delta_q(AH_TARGET, "Ah Target", U16, Rw).short("Ah target").scaled(3, AH)),
        /// 2251h charge cycle elapsed time (ours, seconds; see
        /// [`charge::ELAPSED_TIME`](super::charge::ELAPSED_TIME)).
        elapsed_s: u32 = delta_q(ELAPSED_TIME, "Charge Cycle Elapsed Time", U32, Ro)
            .short("charge cycle elapsed time"),
    }
    without_field {
        // 2FFAh: the padding objects of the Delta-Q PDO mappings (sub 0 =
        // 2, two writable dummy bytes that store nothing).
        ObjectRow::var(index::PADDING, "NrOfEntries", U8, Const)
            .heads("Zero-Filling", ObjectType::Array)
            .short("padding: highest sub-index")
            .default(2),
        ObjectRow::new(Address::new(index::PADDING, 1), "ZeroRxFilling", U8, Rw)
            .mappable()
            .short("padding")
            .reading(Interpretation::Padding),
        ObjectRow::new(Address::new(index::PADDING, 2), "ZeroTxFilling", U8, Rw)
            .mappable()
            .short("padding")
            .reading(Interpretation::Padding),
    }
}

/// The charger's application dictionary as its device core serves it.
pub type ChargerDictionary = FixedDictionary<ChargerObjects>;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abort::AbortCode;
    use crate::od::ObjectDictionary;

    const PADDING: u16 = index::PADDING;

    /// The single-value rows of the table (2FFAh aside), as (index,
    /// access, length).
    fn single_values() -> impl Iterator<Item = (u16, Access, usize)> {
        DELTAQ_OBJECTS
            .iter()
            .filter(|r| r.address.index != PADDING)
            .map(|r| (r.address.index, r.access, usize::from(r.size())))
    }

    /// Every row is named (as its EDS spells it and for the decoder),
    /// fixed-size, PDO-mappable but 2FFAh sub 0, and found by its address.
    #[test]
    fn every_row_is_named_sized_and_found() {
        for row in DELTAQ_OBJECTS {
            assert!(!row.name.is_empty() && !row.short.is_empty(), "{row:?}");
            assert!(matches!(row.size(), 1 | 2 | 4), "{row:?}");
            assert_eq!(row.mappable, row.address != Address::index(PADDING));
            let found = ObjectRow::find(DELTAQ_OBJECTS, row.address).unwrap();
            assert_eq!(found, row);
        }
        assert_eq!(DELTAQ_OBJECTS.len(), 24);
        // Reset node restores the writable rows but padding.
        let writable = DELTAQ_OBJECTS
            .iter()
            .filter(|r| r.access.is_writable() && r.address.index != PADDING);
        assert!(writable
            .map(|r| (r.address.index, r.address.sub))
            .eq(CHARGER_PARAMETERS_RESTORED));
    }

    /// Every object's access, length and field: written (if writable)
    /// and read back through the dictionary, the field changed with it.
    #[test]
    fn every_object_writes_and_reads_its_own_field() {
        let mut o = FixedDictionary::new(ChargerObjects::new());
        let fresh = o;
        for (index, access, len) in single_values() {
            let info = o.info(index, 0).unwrap();
            assert_eq!(
                (info.access, info.len, info.pdo_mappable),
                (access, len, true)
            );
            let value = [0xA1, 0xB2, 0xC3, 0xD4];
            let data = &value[..len];
            o.write(index, 0, 0, data).unwrap();
            let result = o.finish_write(index, 0, len);
            let mut buf = [0u8; 4];
            assert_eq!(o.read(index, 0, 0, &mut buf), Ok(len));
            if access == Access::ReadWrite {
                assert_eq!(result, Ok(()), "{index:04X}h");
                assert_eq!(&buf[..len], data, "{index:04X}h");
            } else {
                assert_eq!(result, Err(AbortCode::WriteOfReadOnlyObject));
                let mut before = [0u8; 4];
                let mut fresh = fresh;
                assert_eq!(fresh.read(index, 0, 0, &mut before), Ok(len));
                assert_eq!(buf, before, "{index:04X}h unchanged");
            }
        }
        assert_eq!(o.battery_status, 0xA1);
        assert_eq!(o.temperature, 0xB2A1_u16 as i16);
        assert_eq!(o.battery_voltage, 0xD4C3_B2A1);
        assert_eq!(o.external_override, 0xA1);
        assert_eq!(o.voltage_request_q8, 0xB2A1);
        assert_eq!(o.extended_status, 0);
        let w16 = 0xB2A1;
        let w32 = 0xD4C3_B2A1;
        assert_eq!(
            (
                o.charging_current,
                o.battery_voltage_q8,
                o.ah_returned,
                o.current_requested
            ),
            (w16, w16, w16, w16)
        );
        assert_eq!((o.algorithm_request, o.voltage_request), (w32, w32));
        assert_eq!(
            (o.battery_soc, o.charger_status, o.charger_soc),
            (0xA1, 0, 0xFF)
        );
        assert_eq!(
            (o.displayed_error, o.battery_voltage_q10, o.ac_voltage),
            (0, 0xFFFF, 0xFFFF)
        );
        // 2FFAh: sub 0 constant, subs 1 and 2 take and drop a byte.
        assert_eq!(o.info(0x2FFA, 0).unwrap().access, Access::Const);
        o.write(0x2FFA, 1, 0, &[7]).unwrap();
        assert_eq!(o.finish_write(0x2FFA, 1, 1), Ok(()));
        o.write(0x2FFA, 0, 0, &[3]).unwrap(); // checked when complete
        assert_eq!(
            o.finish_write(0x2FFA, 0, 1),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
        assert_eq!(o.info(0x6000, 1), Err(AbortCode::SubIndexDoesNotExist));
        // A write of a missing sub-object is refused with the code `info`
        // gives it.
        o.write(0x6000, 1, 0, &[1]).unwrap();
        assert_eq!(
            o.finish_write(0x6000, 1, 1),
            Err(AbortCode::SubIndexDoesNotExist)
        );
    }

    /// Every refusal through the dictionary, object by object: a missing
    /// object (06020000h) or sub-index (06090011h), a read-only object
    /// (06010002h), a value longer (06070012h) or shorter (06070013h) than
    /// the object; a refused write changes nothing and leaves nothing
    /// buffered for the next one.
    #[test]
    fn every_refusal_has_its_code_and_changes_nothing() {
        // The values (the dictionary's buffer keeps the bytes of the last
        // value).
        let values = |o: &ChargerDictionary| *o.objects();
        let mut o = FixedDictionary::new(ChargerObjects::new());
        let before = values(&o);
        let finish = |o: &mut ChargerDictionary, index: u16, sub: u8, data: &[u8]| {
            o.write(index, sub, 0, data)
                .and_then(|()| o.finish_write(index, sub, data.len()))
        };
        for (index, ..) in single_values() {
            let info = o.info(index, 0).unwrap();
            let len = info.len;
            let long = [0x5Au8; 5];
            if info.access.is_writable() {
                assert_eq!(
                    finish(&mut o, index, 0, &long[..len + 1]),
                    Err(AbortCode::DataTypeLengthTooHigh),
                    "{index:04X}h"
                );
                if len > 1 {
                    assert_eq!(
                        finish(&mut o, index, 0, &long[..len - 1]),
                        Err(AbortCode::DataTypeLengthTooLow),
                        "{index:04X}h"
                    );
                }
                // A declared length shorter than the bytes written.
                o.write(index, 0, 0, &long[..len]).unwrap();
                assert_eq!(
                    o.finish_write(index, 0, len.saturating_sub(1)),
                    Err(AbortCode::DataTypeLengthTooLow),
                    "{index:04X}h"
                );
            } else {
                assert_eq!(
                    finish(&mut o, index, 0, &long[..len]),
                    Err(AbortCode::WriteOfReadOnlyObject),
                    "{index:04X}h"
                );
            }
            for sub in [1u8, 2, 0xFF] {
                assert_eq!(o.info(index, sub), Err(AbortCode::SubIndexDoesNotExist));
                assert_eq!(
                    o.read(index, sub, 0, &mut [0; 4]),
                    Err(AbortCode::SubIndexDoesNotExist)
                );
                assert_eq!(
                    finish(&mut o, index, sub, &long[..len]),
                    Err(AbortCode::SubIndexDoesNotExist)
                );
            }
            // Nothing left buffered: a finish without a write takes no bytes.
            if info.access.is_writable() {
                assert_eq!(
                    o.finish_write(index, 0, len),
                    Err(AbortCode::DataTypeLengthTooLow),
                    "{index:04X}h"
                );
            }
        }
        assert_eq!(values(&o), before, "a refused write changes nothing");
        for index in [0x1000u16, 0x2000, 0x2FF9, 0x2FFB, 0x6002, 0x6090, 0xFFFF] {
            assert_eq!(o.info(index, 0), Err(AbortCode::ObjectDoesNotExist));
            assert_eq!(
                o.read(index, 0, 0, &mut [0; 4]),
                Err(AbortCode::ObjectDoesNotExist)
            );
            assert_eq!(
                finish(&mut o, index, 0, &[1]),
                Err(AbortCode::ObjectDoesNotExist)
            );
        }
        // 2FFAh: sub 0 = 2 (constant, not mappable), subs 1 and 2 one
        // writable byte each that reads 0, sub 3 missing.
        let info = o.info(PADDING, 0).unwrap();
        assert_eq!(
            (info.access, info.len, info.pdo_mappable),
            (Access::Const, 1, false)
        );
        let mut buf = [0u8; 1];
        assert_eq!(o.read(PADDING, 0, 0, &mut buf), Ok(1));
        assert_eq!(buf, [2]);
        for sub in [1u8, 2] {
            let info = o.info(PADDING, sub).unwrap();
            assert_eq!(
                (info.access, info.len, info.pdo_mappable),
                (Access::ReadWrite, 1, true)
            );
            assert_eq!(finish(&mut o, PADDING, sub, &[9]), Ok(()));
            assert_eq!(o.read(PADDING, sub, 0, &mut buf), Ok(1));
            assert_eq!(buf, [0], "2FFAh:{sub} stores nothing");
            assert_eq!(
                finish(&mut o, PADDING, sub, &[9, 9]),
                Err(AbortCode::DataTypeLengthTooHigh)
            );
        }
        assert_eq!(
            finish(&mut o, PADDING, 0, &[2]),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
        assert_eq!(o.info(PADDING, 3), Err(AbortCode::SubIndexDoesNotExist));
        assert_eq!(values(&o), before, "2FFAh stores nothing");
        // A value in two pieces, and an aborted one.
        o.write(0x2241, 0, 0, &[1, 2]).unwrap();
        o.write(0x2241, 0, 2, &[3, 4]).unwrap();
        assert_eq!(o.finish_write(0x2241, 0, 4), Ok(()));
        assert_eq!(o.algorithm_request, 0x0403_0201);
        o.write(0x2241, 0, 0, &[9, 9, 9, 9]).unwrap();
        o.abort_write(0x2241, 0);
        assert_eq!(
            o.finish_write(0x2241, 0, 4),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        assert_eq!(o.algorithm_request, 0x0403_0201);
        let mut buf = [0u8; 4];
        assert_eq!(o.read(0x2241, 0, 1, &mut buf), Ok(3));
        assert_eq!(buf[..3], [2, 3, 4]);
        assert_eq!(o.read(0x2241, 0, 4, &mut buf), Ok(0));
        assert_eq!(o.read(0x2241, 0, usize::MAX, &mut buf), Ok(0));
    }

    #[test]
    fn objects_and_access() {
        let mut o = FixedDictionary::new(ChargerObjects::new());
        assert!(o.info(0x2002, 0).unwrap().pdo_mappable);
        assert!(o.info(0x2FFA, 1).unwrap().pdo_mappable);
        assert_eq!(o.info(0x6001, 0).unwrap().access, Access::ReadOnly);
        assert_eq!(o.info(0x6000, 1), Err(AbortCode::SubIndexDoesNotExist));
        assert_eq!(o.info(0x6090, 0), Err(AbortCode::ObjectDoesNotExist));
        assert_eq!(o.info(0x1000, 0), Err(AbortCode::ObjectDoesNotExist));
        let mut buf = [0u8; 8];
        assert_eq!(o.read(0x2276, 0, 0, &mut buf), Ok(2));
        assert_eq!(buf[..2], [0xFF, 0xFF]);
        assert_eq!(o.read(0x2241, 0, 2, &mut buf), Ok(2));
        o.write(0x6000, 0, 0, &[1]).unwrap();
        o.finish_write(0x6000, 0, 1).unwrap();
        assert_eq!(o.battery_status, 1);
        o.write(0x2006, 0, 0, &[1, 0]).unwrap();
        assert_eq!(
            o.finish_write(0x2006, 0, 2),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
    }
}
