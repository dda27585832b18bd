//! The application objects of a CiA 418 battery module as a fixed struct,
//! no allocation: [`BatteryObjects`] declares every application object
//! 6000h-6090h of CiA 418 v1.0.1 (section 7.3) for the crate's fixed-word
//! dictionary ([`FixedDictionary`], which serves them by SDO). The communication
//! objects (1000h, 1001h, 1003h, 1008h, 1017h, 1018h, 1200h) and the PDO
//! objects (1400h-1A03h) are the device core's
//! ([`crate::device::CommObjects`], [`PdoDictionary`](crate::pdo::PdoDictionary)).
//!
//! | index | object | type | access | PDO |
//! |---|---|---|---|---|
//! | 6000h | battery status | U8 | ro | yes |
//! | 6001h | charger status | U8 | rw | yes |
//! | 6010h | temperature | I16 | ro | yes |
//! | 6020h | battery parameters (sub 0 = 4) | RECORD | ro | |
//! | 6030h, 6031h, 6040h, 6041h | packed strings (sub 0 = element count) | ARRAY of U32 | ro | |
//! | 6050h | cumulative total Ah charge | U32 | ro | |
//! | 6051h | Ah expended since last charge | U16 | ro | |
//! | 6052h | Ah returned during last charge | U16 | rw | yes |
//! | 6053h | Ah since last equalization | U16 | rw | |
//! | 6054h | date of last equalization (sub 0 = 2, ro) | ARRAY of U16 | rw | |
//! | 6060h | battery voltage | U32 | ro | yes |
//! | 6070h | charge current requested | U16 | ro | yes |
//! | 6080h | charger state of charge | U8 | rw | yes |
//! | 6081h | battery state of charge | U8 | ro | yes |
//! | 6090h | water level status | U8 | ro | |
//!
//! A missing object is 06020000h, a missing sub-index 06090011h, a write to
//! a `ro`/`const` object 06010002h, a wrong length 06070012h/06070013h
//! ([`FixedDictionary`]'s rules). Writes are applied whole at
//! [`finish_write`](crate::od::ObjectDictionary::finish_write). Two value
//! checks (our choice; CiA 418 names the ranges but no abort code): 6080h
//! accepts 0..=100 and FFh (invalid), anything else is 06090031h (value too
//! high); 6054h sub 1 (minutes since midnight) accepts 0..=1439, anything
//! else is 06090031h.
//!
//! NMT reset node sets the `rw` objects (6001h, 6052h, 6053h, 6054h, 6080h:
//! what the charger writes by SDO or RPDO, the parameters) back to their
//! values at boot ([`BATTERY_PARAMETERS_RESTORED`]); the `ro` objects are the
//! application's measurements and identity and keep the value it last set
//! (a boot-time reading restored would be published until its next update).

use super::CIA418_OBJECTS;
use super::{AmpHours, EighthAmpHours};
use super::{
    BatteryParameters, BatteryStatus, BatteryVoltage, ChargeCurrentRequested, ChargerStatus,
    EqualizationDate, PackedString, PackedStringError, PackedStringObject, StateOfCharge,
    Temperature, WaterLevelStatus, AH_EXPENDED_SINCE_LAST_CHARGE, AH_RETURNED_DURING_LAST_CHARGE,
    AH_SINCE_LAST_EQUALIZATION, BATTERY_PARAMETERS, BATTERY_SERIAL_NUMBER, BATTERY_STATE_OF_CHARGE,
    BATTERY_STATUS, BATTERY_VOLTAGE, CHARGER_STATE_OF_CHARGE, CHARGER_STATUS,
    CHARGE_CURRENT_REQUESTED, CUMULATIVE_TOTAL_AH_CHARGE, DATE_OF_LAST_EQUALIZATION, TEMPERATURE,
    WATER_LEVEL_STATUS,
};
use crate::abort::AbortCode;
use crate::od::{Access, FixedDictionary, FixedEntry, FixedObjects, ObjectRow};

/// Every index [`BatteryObjects`] serves: the objects of
/// [`CIA418_OBJECTS`], each once, in the table's order.
pub const BATTERY_OBJECT_INDEXES: [u16; ObjectRow::object_count(CIA418_OBJECTS)] =
    ObjectRow::object_indexes(CIA418_OBJECTS);

/// A packed-string ARRAY as stored: element count and elements.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct PackedValue {
    count: u8,
    words: [u32; 5],
}

impl PackedValue {
    /// The empty string: one zero element.
    const EMPTY: PackedValue = PackedValue {
        count: 1,
        words: [0; 5],
    };

    fn word(&self, sub: u8) -> Option<u32> {
        if sub == 0 || sub > self.count {
            return None;
        }
        self.words.get(usize::from(sub) - 1).copied()
    }
}

/// The values of a CiA 418 battery module's objects (see the module docs
/// for the table). The application sets the fields it measures; the
/// charger writes the `rw` ones through SDO or RPDOs.
///
/// ```
/// use canopen_codec::cia418::{BatteryObjects, Temperature};
/// use canopen_codec::od::{FixedDictionary, ObjectDictionary};
/// let mut od = FixedDictionary::new(BatteryObjects::new());
/// od.temperature = Temperature::from_celsius(25).unwrap();
/// let mut buf = [0u8; 2];
/// assert_eq!(od.read(0x6010, 0, 0, &mut buf), Ok(2));
/// assert_eq!(buf, [0xC8, 0x00]); // 200 * 0.125 degC
/// assert!(od.info(0x6010, 0).unwrap().pdo_mappable);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BatteryObjects {
    /// 6054h date of last equalization (rw).
    pub date_of_last_equalization: EqualizationDate,
    /// 6052h Ah returned during last charge (rw).
    pub ah_returned_during_last_charge: EighthAmpHours,
    /// 6053h Ah since last equalization (rw).
    pub ah_since_last_equalization: EighthAmpHours,
    /// 6001h charger status (written by the charger).
    pub charger_status: ChargerStatus,
    /// 6080h charger state of charge (written by the charger; default FFh).
    pub charger_state_of_charge: StateOfCharge,
    /// 6000h battery status.
    pub battery_status: BatteryStatus,
    /// 6010h temperature.
    pub temperature: Temperature,
    /// 6020h battery parameters.
    pub battery_parameters: BatteryParameters,
    /// 6050h cumulative total Ah charge.
    pub cumulative_total_ah_charge: AmpHours,
    /// 6051h Ah expended since last charge.
    pub ah_expended_since_last_charge: EighthAmpHours,
    /// 6060h battery voltage.
    pub battery_voltage: BatteryVoltage,
    /// 6070h charge current requested.
    pub charge_current_requested: ChargeCurrentRequested,
    /// 6081h battery state of charge (default FFh, invalid).
    pub battery_state_of_charge: StateOfCharge,
    /// 6090h water level status.
    pub water_level: WaterLevelStatus,
    /// 6030h, 6031h, 6040h, 6041h in [`PackedStringObject::ALL`] order.
    packed: [PackedValue; 4],
}

/// The SDO facts (access, size, PDO mapping) of entry `index` sub `sub`
/// as its row in [`CIA418_OBJECTS`] states them, evaluated when the crate
/// is built (an entry without a row reads as an empty constant).
const fn facts(index: u16, sub: u8) -> FixedEntry {
    let mut rows = CIA418_OBJECTS;
    while let [row, rest @ ..] = rows {
        if row.covers(index, sub) {
            return row.entry(row.default);
        }
        rows = rest;
    }
    FixedEntry::new(Access::Const, 0, 0)
}

fn packed_slot(object: PackedStringObject) -> usize {
    match object {
        PackedStringObject::BatterySerialNumber => 0,
        PackedStringObject::BatteryId => 1,
        PackedStringObject::VehicleSerialNumber => 2,
        PackedStringObject::VehicleId => 3,
    }
}

impl Default for BatteryObjects {
    fn default() -> Self {
        Self::new()
    }
}

impl BatteryObjects {
    /// The power-on values: everything zero except the two states of
    /// charge (FFh, invalid), the charge current requested (FFFFh, invalid)
    /// and the packed strings (empty, one element).
    #[must_use]
    pub const fn new() -> Self {
        BatteryObjects {
            battery_status: BatteryStatus::empty(),
            charger_status: ChargerStatus::empty(),
            temperature: Temperature::from_raw(0),
            battery_parameters: BatteryParameters {
                battery_type: super::BatteryType::Unknown(0),
                ah_capacity: 0,
                max_charge_current: 0,
                number_of_cells: 0,
            },
            cumulative_total_ah_charge: AmpHours::from_raw(0),
            ah_expended_since_last_charge: EighthAmpHours::from_raw(0),
            ah_returned_during_last_charge: EighthAmpHours::from_raw(0),
            ah_since_last_equalization: EighthAmpHours::from_raw(0),
            date_of_last_equalization: EqualizationDate {
                minutes: 0,
                days: 0,
            },
            battery_voltage: BatteryVoltage::from_raw(0),
            charge_current_requested: ChargeCurrentRequested::INVALID,
            charger_state_of_charge: StateOfCharge::INVALID,
            battery_state_of_charge: StateOfCharge::INVALID,
            water_level: WaterLevelStatus::empty(),
            packed: [PackedValue::EMPTY; 4],
        }
    }

    /// Stores a packed string (6030h, 6031h, 6040h, 6041h).
    pub fn set_packed_string(&mut self, value: &PackedString) {
        if let Some(slot) = self.packed.get_mut(packed_slot(value.object())) {
            let mut words = [0u32; 5];
            for (d, s) in words.iter_mut().zip(value.words()) {
                *d = *s;
            }
            *slot = PackedValue {
                count: value.count(),
                words,
            };
        }
    }

    /// Packs `text` into `object` with the fewest elements and stores it.
    pub fn set_text(
        &mut self,
        object: PackedStringObject,
        text: &str,
    ) -> Result<(), PackedStringError> {
        let p = PackedString::encode(object, text)?;
        self.set_packed_string(&p);
        Ok(())
    }

    /// The stored packed string of `object`.
    pub fn packed_string(
        &self,
        object: PackedStringObject,
    ) -> Result<PackedString, PackedStringError> {
        let v = self
            .packed
            .get(packed_slot(object))
            .copied()
            .unwrap_or(PackedValue::EMPTY);
        PackedString::decode(object, v.count, &v.words)
    }

    /// True if the dictionary has object `index` (any sub-index).
    #[must_use]
    pub fn has_object(index: u16) -> bool {
        BATTERY_OBJECT_INDEXES.contains(&index)
    }

    /// The entry of single-value object `index` (sub-index 0): its
    /// field's value, with the access, size and PDO mapping its row in
    /// [`CIA418_OBJECTS`] gives; `None` for the others.
    fn scalar(&self, index: u16) -> Option<FixedEntry> {
        // One arm per object, its index written once: the value, and the
        // facts of its row evaluated when the crate is built.
        macro_rules! scalars {
            ($($object:ident => $word:expr,)*) => {
                match index {
                    $($object => (u32::from($word), const { facts($object, 0) }),)*
                    _ => return None,
                }
            };
        }
        let (word, entry) = scalars! {
            BATTERY_STATUS => self.battery_status.bits(),
            CHARGER_STATUS => self.charger_status.bits(),
            TEMPERATURE => self.temperature.raw() as u16,
            CUMULATIVE_TOTAL_AH_CHARGE => self.cumulative_total_ah_charge.raw(),
            AH_EXPENDED_SINCE_LAST_CHARGE => self.ah_expended_since_last_charge.raw(),
            AH_RETURNED_DURING_LAST_CHARGE => self.ah_returned_during_last_charge.raw(),
            AH_SINCE_LAST_EQUALIZATION => self.ah_since_last_equalization.raw(),
            BATTERY_VOLTAGE => self.battery_voltage.raw(),
            CHARGE_CURRENT_REQUESTED => self.charge_current_requested.raw(),
            CHARGER_STATE_OF_CHARGE => self.charger_state_of_charge.raw(),
            BATTERY_STATE_OF_CHARGE => self.battery_state_of_charge.raw(),
            WATER_LEVEL_STATUS => self.water_level.bits(),
        };
        Some(FixedEntry { word, ..entry })
    }

    /// The entries of the objects with sub-indexes: 6020h's record,
    /// 6054h's array and the packed strings' element counts and elements,
    /// with the facts of their rows; 06090011h for a sub-index the object
    /// lacks (a packed string has as many elements as it stores),
    /// 06020000h for an object the table lacks.
    fn compound_entry(&self, index: u16, sub: u8) -> Result<FixedEntry, AbortCode> {
        use EqualizationDate as Date;
        const DATE: u16 = DATE_OF_LAST_EQUALIZATION;
        let missing_sub = AbortCode::SubIndexDoesNotExist;
        let (word, entry) = match (index, sub) {
            (DATE, 0) => (Date::NUMBER_OF_ELEMENTS.into(), const { facts(DATE, 0) }),
            (DATE, Date::SUB_MINUTES) => (
                self.date_of_last_equalization.minutes.into(),
                const { facts(DATE, Date::SUB_MINUTES) },
            ),
            (DATE, Date::SUB_DAYS) => (
                self.date_of_last_equalization.days.into(),
                const { facts(DATE, Date::SUB_DAYS) },
            ),
            (BATTERY_PARAMETERS, _) => {
                let (word, len) = self.battery_parameters.sub_word(sub).ok_or(missing_sub)?;
                let entry = const { facts(BATTERY_PARAMETERS, 0) };
                (word.into(), FixedEntry { len, ..entry })
            }
            _ => {
                let Some(object) = PackedStringObject::from_index(index) else {
                    return Err(if Self::has_object(index) {
                        missing_sub
                    } else {
                        AbortCode::ObjectDoesNotExist
                    });
                };
                let v = self
                    .packed
                    .get(packed_slot(object))
                    .unwrap_or(&PackedValue::EMPTY);
                // The four packed strings' rows differ only in their last
                // sub-index (`packed_count`, `packed`), which `v.word`
                // enforces.
                if sub == 0 {
                    (v.count.into(), const { facts(BATTERY_SERIAL_NUMBER, 0) })
                } else {
                    let word = v.word(sub).ok_or(missing_sub)?;
                    (word, const { facts(BATTERY_SERIAL_NUMBER, 1) })
                }
            }
        };
        Ok(FixedEntry { word, ..entry })
    }
}

/// What NMT reset node restores of [`BatteryObjects`]: its `rw` objects
/// (6001h, 6052h, 6053h, 6054h, 6080h: what the charger writes by SDO or
/// RPDO; the writable rows of [`CIA418_OBJECTS`]) as they were at boot. The `ro` objects are not in it: they are
/// the module's measurements and identity, not parameters (CiA 301
/// 7.3.2.2.1: reset node restores the parameters of the profile areas),
/// and keep what the application last set, so no stale boot-time reading
/// is published until its next update.
pub const BATTERY_PARAMETERS_RESTORED: [(u16, u8); ObjectRow::parameter_count(CIA418_OBJECTS)] =
    ObjectRow::parameters(CIA418_OBJECTS);

/// The values of [`BATTERY_PARAMETERS_RESTORED`] kept at boot, their bytes
/// one after the other (1 + 2 + 2 + 2 + 2 + 1).
///
/// ```
/// use canopen_codec::cia418::{BatteryObjects, StateOfCharge, Temperature};
/// use canopen_codec::device::PowerOnValues;
/// use canopen_codec::od::FixedDictionary;
/// let mut od = FixedDictionary::new(BatteryObjects::new());
/// let at_boot = od.snapshot();
/// od.charger_state_of_charge = StateOfCharge::from_raw(80); // written by the charger
/// od.temperature = Temperature::from_celsius(30).unwrap(); // measured
/// od.restore(&at_boot); // reset node
/// assert_eq!(od.charger_state_of_charge, StateOfCharge::INVALID);
/// assert_eq!(od.temperature, Temperature::from_celsius(30).unwrap());
/// ```
pub type BatteryPowerOnValues = [u8; ObjectRow::parameter_bytes(CIA418_OBJECTS)];

impl FixedObjects for BatteryObjects {
    type Parameters = BatteryPowerOnValues;
    const PARAMETERS: &'static [(u16, u8)] = &BATTERY_PARAMETERS_RESTORED;

    fn entry(&self, index: u16, sub: u8) -> Result<FixedEntry, AbortCode> {
        match self.scalar(index) {
            Some(_) if sub != 0 => Err(AbortCode::SubIndexDoesNotExist),
            Some(entry) => Ok(entry),
            None => self.compound_entry(index, sub),
        }
    }

    /// Two ranges (our choice; CiA 418 names them but no abort code):
    /// 6080h 0..=100 or FFh (invalid), 6054h sub 1 (minutes since
    /// midnight) 0..=1439; anything else is 06090031h (value too high).
    fn check(&self, index: u16, sub: u8, word: u32) -> Result<(), AbortCode> {
        let too_high = match (index, sub) {
            (CHARGER_STATE_OF_CHARGE, _) => StateOfCharge::from_raw(word as u8).is_out_of_range(),
            (DATE_OF_LAST_EQUALIZATION, EqualizationDate::SUB_MINUTES) => word >= 1440,
            _ => false,
        };
        if too_high {
            return Err(AbortCode::ValueTooHigh);
        }
        Ok(())
    }

    fn store(&mut self, _: &FixedEntry, index: u16, sub: u8, word: u32) {
        let [a, b, ..] = word.to_le_bytes();
        let half = u16::from_le_bytes([a, b]);
        match (index, sub) {
            (CHARGER_STATUS, 0) => self.charger_status = ChargerStatus::from_bits_retain(a),
            (AH_RETURNED_DURING_LAST_CHARGE, 0) => {
                self.ah_returned_during_last_charge = EighthAmpHours::from_raw(half);
            }
            (AH_SINCE_LAST_EQUALIZATION, 0) => {
                self.ah_since_last_equalization = EighthAmpHours::from_raw(half);
            }
            (DATE_OF_LAST_EQUALIZATION, EqualizationDate::SUB_MINUTES) => {
                self.date_of_last_equalization.minutes = half;
            }
            (DATE_OF_LAST_EQUALIZATION, EqualizationDate::SUB_DAYS) => {
                self.date_of_last_equalization.days = half;
            }
            (CHARGER_STATE_OF_CHARGE, 0) => {
                self.charger_state_of_charge = StateOfCharge::from_raw(a)
            }
            _ => {}
        }
    }
}

/// The module's application dictionary as its device core serves it.
pub type BatteryDictionary = FixedDictionary<BatteryObjects>;

#[cfg(test)]
#[path = "objects_tests.rs"]
mod tests;
