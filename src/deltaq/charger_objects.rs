//! The Delta-Q charger's application objects: the CiA 418 objects a CiA
//! 419 charger shares with the battery module (6000h-6081h) and the
//! Delta-Q manufacturer objects (Delta-Q IC Series CANopen interface
//! specification rev 2.0, section 5: 2002h, 2006h, 2008h, 2060h, 2100h,
//! 2101h, 2200h, 2241h, 2271h, 2276h, 4201h, and the 2FFAh padding objects
//! its PDO mappings use), and the two objects of the charge control the
//! documents do not name (ours: 2250h Ah target, 2251h elapsed time; see
//! [`charge`](super::charge)), declared for the crate's fixed-word dictionary
//! ([`FixedDictionary`], which serves them by SDO). Fixed storage, no
//! allocation. The communication objects (1000h-1FFFh) are the device
//! core's ([`crate::device`]).
//!
//! NMT reset node sets the writable objects (what the battery module's
//! TPDOs and an SDO client write: the parameters) back to their values at
//! boot ([`CHARGER_PARAMETERS_RESTORED`]); the read-only ones (6001h,
//! 6080h, 2006h, 2060h, 2100h, 2200h) are the charger's own readings and
//! state and keep the value the application last set (a boot-time value
//! restored would be published until its next update).

use crate::abort::AbortCode;
use crate::od::{Access, FixedDictionary, FixedEntry, FixedObject, FixedObjects};

/// The charger's object values. Fields are the application's to read and
/// write; SDO access goes through [`FixedDictionary`] with the access
/// rights of each object ([`ChargerDictionary`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargerObjects {
    /// 6000h battery status (written by the BMS).
    pub battery_status: u8,
    /// 6001h charger status (bit 0: able to charge).
    pub charger_status: u8,
    /// 6010h battery temperature (0.125 degC).
    pub temperature: i16,
    /// 6052h Ah returned (Delta-Q: Q3 Ah, FFFFh no value).
    pub ah_returned: u16,
    /// 6060h battery voltage (1/1024 V).
    pub battery_voltage: u32,
    /// 6070h charge current requested (1/16 A).
    pub current_requested: u16,
    /// 6080h charger state of charge (%; FFh invalid).
    pub charger_soc: u8,
    /// 6081h battery state of charge (%; FFh invalid).
    pub battery_soc: u8,
    /// 2002h charging current (Q8 A).
    pub charging_current: u16,
    /// 2006h extended charge status.
    pub extended_status: u16,
    /// 2060h current displayed error (a 1003h-style entry; 0 none).
    pub displayed_error: u32,
    /// 2100h battery voltage, legacy (Q10 V).
    pub battery_voltage_q10: u16,
    /// 2101h battery voltage (Q8 V).
    pub battery_voltage_q8: u16,
    /// 2200h AC voltage (Q4 V).
    pub ac_voltage: u16,
    /// 2241h active algorithm request (FFFFFFFFh none).
    pub algorithm_request: u32,
    /// 2271h voltage request (Q10 V, FFFFFFFFh none).
    pub voltage_request: u32,
    /// 2276h voltage request (Q8 V, FFFFh none).
    pub voltage_request_q8: u16,
    /// 4201h external override.
    pub external_override: u8,
    /// 2008h derate reasons.
    pub derate_reasons: u8,
    /// 2250h Ah target (ours, Q3 Ah, FFFFh none; see
    /// [`charge::AH_TARGET`](super::charge::AH_TARGET)).
    pub ah_target: u16,
    /// 2251h charge cycle elapsed time (ours, seconds; see
    /// [`charge::ELAPSED_TIME`](super::charge::ELAPSED_TIME)).
    pub elapsed_s: u32,
}

/// The charger's application dictionary as its device core serves it.
pub type ChargerDictionary = FixedDictionary<ChargerObjects>;

impl Default for ChargerObjects {
    fn default() -> Self {
        Self::new()
    }
}

impl ChargerObjects {
    /// Power-on values: the Delta-Q "no value" markers, SOC invalid.
    #[must_use]
    pub const fn new() -> Self {
        ChargerObjects {
            battery_status: 0,
            charger_status: 0,
            temperature: 0,
            ah_returned: 0xFFFF,
            battery_voltage: 0,
            current_requested: 0xFFFF,
            charger_soc: 0xFF,
            battery_soc: 0xFF,
            charging_current: 0,
            extended_status: 0,
            displayed_error: 0,
            battery_voltage_q10: 0xFFFF,
            battery_voltage_q8: 0xFFFF,
            ac_voltage: 0xFFFF,
            algorithm_request: 0xFFFF_FFFF,
            voltage_request: 0xFFFF_FFFF,
            voltage_request_q8: 0xFFFF,
            external_override: 0,
            derate_reasons: 0,
            ah_target: 0xFFFF,
            elapsed_s: 0,
        }
    }

    /// The field of writable row `row` of [`OBJECTS`]; `None` for the
    /// read-only rows (SDO never stores there) and 2FFAh ([`NO_FIELD`]).
    fn writable_field(&mut self, row: u8) -> Option<Field<'_>> {
        Some(match row {
            0 => Field::U8(&mut self.battery_status),
            2 => Field::I16(&mut self.temperature),
            3 => Field::U16(&mut self.ah_returned),
            4 => Field::U32(&mut self.battery_voltage),
            5 => Field::U16(&mut self.current_requested),
            7 => Field::U8(&mut self.battery_soc),
            8 => Field::U16(&mut self.charging_current),
            12 => Field::U16(&mut self.battery_voltage_q8),
            14 => Field::U32(&mut self.algorithm_request),
            15 => Field::U32(&mut self.voltage_request),
            16 => Field::U16(&mut self.voltage_request_q8),
            17 => Field::U8(&mut self.external_override),
            19 => Field::U16(&mut self.ah_target),
            _ => return None,
        })
    }

    /// The value of row `row` of [`OBJECTS`].
    fn value(&self, row: usize) -> u32 {
        match row {
            0 => self.battery_status.into(),
            1 => self.charger_status.into(),
            2 => u32::from(self.temperature as u16),
            3 => self.ah_returned.into(),
            4 => self.battery_voltage,
            5 => self.current_requested.into(),
            6 => self.charger_soc.into(),
            7 => self.battery_soc.into(),
            8 => self.charging_current.into(),
            9 => self.extended_status.into(),
            10 => self.displayed_error,
            11 => self.battery_voltage_q10.into(),
            12 => self.battery_voltage_q8.into(),
            13 => self.ac_voltage.into(),
            14 => self.algorithm_request,
            15 => self.voltage_request,
            16 => self.voltage_request_q8.into(),
            17 => self.external_override.into(),
            18 => self.derate_reasons.into(),
            19 => self.ah_target.into(),
            _ => self.elapsed_s,
        }
    }
}

/// A writable field of [`ChargerObjects`] by its type.
enum Field<'a> {
    U8(&'a mut u8),
    U16(&'a mut u16),
    I16(&'a mut i16),
    U32(&'a mut u32),
}

/// 2FFAh: the padding objects of the Delta-Q PDO mappings (sub 0 = 2, two
/// writable dummy bytes that store nothing).
const PADDING: u16 = 0x2FFA;

/// [`FixedEntry::slot`] of the 2FFAh padding objects: no field.
const NO_FIELD: u8 = u8::MAX;

/// The charger's objects besides 2FFAh, in the order of the rows of
/// `ChargerObjects::field`: one table for SDO info, reads, writes and what
/// reset node restores (every one PDO-mappable).
const OBJECTS: [FixedObject; 21] = {
    use Access::{ReadOnly as Ro, ReadWrite as Rw};
    const fn object(index: u16, width: u8, access: Access) -> FixedObject {
        FixedObject::new(index, width, access, true)
    }
    [
        object(0x6000, 1, Rw),
        object(0x6001, 1, Ro),
        object(0x6010, 2, Rw),
        object(0x6052, 2, Rw),
        object(0x6060, 4, Rw),
        object(0x6070, 2, Rw),
        object(0x6080, 1, Ro),
        object(0x6081, 1, Rw),
        object(0x2002, 2, Rw),
        object(0x2006, 2, Ro),
        object(0x2060, 4, Ro),
        object(0x2100, 2, Ro),
        object(0x2101, 2, Rw),
        object(0x2200, 2, Ro),
        object(0x2241, 4, Rw),
        object(0x2271, 4, Rw),
        object(0x2276, 2, Rw),
        object(0x4201, 1, Rw),
        object(0x2008, 1, Ro),
        object(0x2250, 2, Rw),
        object(0x2251, 4, Ro),
    ]
};

/// How many rows of [`OBJECTS`] are writable, and their bytes.
const fn writable_rows() -> (usize, usize) {
    let (mut i, mut n, mut bytes) = (0, 0, 0);
    while i < OBJECTS.len() {
        if OBJECTS[i].access.is_writable() {
            n += 1;
            bytes += OBJECTS[i].width as usize;
        }
        i += 1;
    }
    (n, bytes)
}

/// What NMT reset node restores of [`ChargerObjects`]: its writable
/// objects (6000h, 6010h, 6052h, 6060h, 6070h, 6081h, 2002h, 2101h, 2241h,
/// 2271h, 2276h, 4201h, 2250h; 2FFAh stores nothing), the writable rows of
/// its table, as they were at boot. The read-only objects (6001h, 6080h,
/// 2006h, 2008h, 2060h, 2100h, 2200h, 2251h) are the charger's own readings and state,
/// not parameters (CiA 301 7.3.2.2.1: reset node restores the parameters
/// of the profile areas): they keep what the application last set, so no
/// stale boot-time value is published until its next update.
pub const CHARGER_PARAMETERS_RESTORED: [(u16, u8); writable_rows().0] = {
    let mut list = [(0u16, 0u8); writable_rows().0];
    let (mut i, mut n) = (0, 0);
    while i < OBJECTS.len() {
        if OBJECTS[i].access.is_writable() {
            list[n] = (OBJECTS[i].index, 0);
            n += 1;
        }
        i += 1;
    }
    list
};

/// The values of [`CHARGER_PARAMETERS_RESTORED`] kept at boot, their bytes
/// one after the other.
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
pub type ChargerPowerOnValues = [u8; writable_rows().1];

impl FixedObjects for ChargerObjects {
    type Parameters = ChargerPowerOnValues;
    const PARAMETERS: &'static [(u16, u8)] = &CHARGER_PARAMETERS_RESTORED;

    fn entry(&self, index: u16, sub: u8) -> Result<FixedEntry, AbortCode> {
        if index == PADDING {
            let (access, word) = match sub {
                0 => (Access::Const, 2),
                1 | 2 => (Access::ReadWrite, 0),
                _ => return Err(AbortCode::SubIndexDoesNotExist),
            };
            return Ok(FixedEntry {
                mappable: sub != 0,
                slot: NO_FIELD,
                ..FixedEntry::new(access, word, 1)
            });
        }
        FixedObject::lookup(&OBJECTS, index, sub, |row| self.value(row))
            .unwrap_or(Err(AbortCode::ObjectDoesNotExist))
    }

    /// Stores the value in the field of the entry's row; 2FFAh
    /// stores nothing.
    fn store(&mut self, entry: &FixedEntry, _: u16, _: u8, word: u32) {
        // Truncations to the object's width (the value has no more bytes).
        match self.writable_field(entry.slot) {
            Some(Field::U8(f)) => *f = word as u8,
            Some(Field::U16(f)) => *f = word as u16,
            Some(Field::I16(f)) => *f = word as u16 as i16,
            Some(Field::U32(f)) => *f = word,
            None => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::od::ObjectDictionary;

    /// Every object's access, length and field: written (if writable)
    /// and read back through the dictionary, the field changed with it.
    #[test]
    fn every_object_writes_and_reads_its_own_field() {
        use Access::{ReadOnly as Ro, ReadWrite as Rw};
        let expected: [(u16, Access, usize); 21] = [
            (0x6000, Rw, 1),
            (0x6001, Ro, 1),
            (0x6010, Rw, 2),
            (0x6052, Rw, 2),
            (0x6060, Rw, 4),
            (0x6070, Rw, 2),
            (0x6080, Ro, 1),
            (0x6081, Rw, 1),
            (0x2002, Rw, 2),
            (0x2006, Ro, 2),
            (0x2060, Ro, 4),
            (0x2100, Ro, 2),
            (0x2101, Rw, 2),
            (0x2200, Ro, 2),
            (0x2241, Rw, 4),
            (0x2271, Rw, 4),
            (0x2276, Rw, 2),
            (0x4201, Rw, 1),
            (0x2008, Ro, 1),
            (0x2250, Rw, 2),
            (0x2251, Ro, 4),
        ];
        let mut o = FixedDictionary::new(ChargerObjects::new());
        for (index, access, len) in expected {
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
            if access == Rw {
                assert_eq!(result, Ok(()), "{index:04X}h");
                assert_eq!(&buf[..len], data, "{index:04X}h");
            } else {
                assert_eq!(result, Err(AbortCode::WriteOfReadOnlyObject));
                assert_ne!(&buf[..len], data, "{index:04X}h");
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
        let rows: [u16; 18] = [
            0x6000, 0x6001, 0x6010, 0x6052, 0x6060, 0x6070, 0x6080, 0x6081, 0x2002, 0x2006, 0x2060,
            0x2100, 0x2101, 0x2200, 0x2241, 0x2271, 0x2276, 0x4201,
        ];
        let finish = |o: &mut ChargerDictionary, index: u16, sub: u8, data: &[u8]| {
            o.write(index, sub, 0, data)
                .and_then(|()| o.finish_write(index, sub, data.len()))
        };
        for index in rows {
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
