//! The object dictionary of a CiA 418 battery module as a fixed struct, no
//! allocation: [`BatteryObjects`] implements
//! [`ObjectDictionary`](crate::od::ObjectDictionary) for the communication
//! objects 1000h, 1001h, 1008h, 1017h, 1018h, 1200h and every application
//! object 6000h-6090h of CiA 418 (DIGEST section 6). The PDO objects
//! (1400h-1A03h) are layered on top by
//! [`PdoDictionary`](crate::pdo::PdoDictionary).
//!
//! | index | object | type | access | PDO |
//! |---|---|---|---|---|
//! | 1000h | device type | U32 | const | |
//! | 1001h | error register | U8 | ro | |
//! | 1008h | manufacturer device name | VISIBLE_STRING | const | |
//! | 1017h | producer heartbeat time (ms) | U16 | rw | |
//! | 1018h | identity (sub 0 = 4; vendor, product, revision, serial) | RECORD of U32 | ro | |
//! | 1200h | SDO server parameter (sub 0 = 2; 600h + node, 580h + node) | RECORD of U32 | ro | |
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
//! a `ro`/`const` object 06010002h, a wrong length 06070012h/06070013h.
//! Writes are applied whole at
//! [`finish_write`](crate::od::ObjectDictionary::finish_write). Two value
//! checks (our choice; CiA 418 names the ranges but no abort code): 6080h
//! accepts 0..=100 and FFh (invalid), anything else is 06090031h (value too
//! high); 6054h sub 1 (minutes since midnight) accepts 0..=1439, anything
//! else is 06090031h.

use super::{AmpHours, EighthAmpHours};
use super::{
    BatteryParameters, BatteryStatus, BatteryVoltage, ChargeCurrentRequested, ChargerStatus,
    DeviceType, EqualizationDate, PackedString, PackedStringError, PackedStringObject,
    StateOfCharge, Temperature, WaterLevelStatus, AH_EXPENDED_SINCE_LAST_CHARGE,
    AH_RETURNED_DURING_LAST_CHARGE, AH_SINCE_LAST_EQUALIZATION, BATTERY_ID, BATTERY_PARAMETERS,
    BATTERY_SERIAL_NUMBER, BATTERY_STATE_OF_CHARGE, BATTERY_STATUS, BATTERY_VOLTAGE,
    CHARGER_STATE_OF_CHARGE, CHARGER_STATUS, CHARGE_CURRENT_REQUESTED, CUMULATIVE_TOTAL_AH_CHARGE,
    DATE_OF_LAST_EQUALIZATION, DEVICE_TYPE, ERROR_REGISTER, TEMPERATURE, VEHICLE_ID,
    VEHICLE_SERIAL_NUMBER, WATER_LEVEL_STATUS,
};
use crate::cob_id::{NodeId, SDO_RX_BASE, SDO_TX_BASE};
use crate::emcy::ErrorRegister;
use crate::od::index::{
    IDENTITY, MANUFACTURER_DEVICE_NAME, PRODUCER_HEARTBEAT_TIME, SDO_SERVER_PARAMETER,
};
use crate::od::{Access, ObjectDictionary, ObjectInfo};
use crate::sdo::AbortCode;

/// Every index [`BatteryObjects`] serves.
pub const BATTERY_OBJECT_INDEXES: [u16; 24] = [
    DEVICE_TYPE,
    ERROR_REGISTER,
    MANUFACTURER_DEVICE_NAME,
    PRODUCER_HEARTBEAT_TIME,
    IDENTITY,
    SDO_SERVER_PARAMETER,
    BATTERY_STATUS,
    CHARGER_STATUS,
    TEMPERATURE,
    BATTERY_PARAMETERS,
    BATTERY_SERIAL_NUMBER,
    BATTERY_ID,
    VEHICLE_SERIAL_NUMBER,
    VEHICLE_ID,
    CUMULATIVE_TOTAL_AH_CHARGE,
    AH_EXPENDED_SINCE_LAST_CHARGE,
    AH_RETURNED_DURING_LAST_CHARGE,
    AH_SINCE_LAST_EQUALIZATION,
    DATE_OF_LAST_EQUALIZATION,
    BATTERY_VOLTAGE,
    CHARGE_CURRENT_REQUESTED,
    CHARGER_STATE_OF_CHARGE,
    BATTERY_STATE_OF_CHARGE,
    WATER_LEVEL_STATUS,
];

/// 1018h identity object: sub 1-4 (CiA 301).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Identity {
    /// Sub 1: vendor-ID (assigned by CiA).
    pub vendor_id: u32,
    /// Sub 2: product code.
    pub product_code: u32,
    /// Sub 3: revision number.
    pub revision_number: u32,
    /// Sub 4: serial number.
    pub serial_number: u32,
}

impl Identity {
    /// Value of sub 0, highest sub-index supported.
    pub const HIGHEST_SUB_INDEX: u8 = 4;

    /// The value of sub-index `sub` (1..=4).
    #[must_use]
    pub const fn sub(&self, sub: u8) -> Option<u32> {
        match sub {
            1 => Some(self.vendor_id),
            2 => Some(self.product_code),
            3 => Some(self.revision_number),
            4 => Some(self.serial_number),
            _ => None,
        }
    }
}

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

/// A value of at most 4 bytes, little-endian.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Value {
    bytes: [u8; 4],
    len: usize,
}

impl Value {
    fn from_slice(data: &[u8]) -> Self {
        let mut bytes = [0u8; 4];
        for (d, s) in bytes.iter_mut().zip(data) {
            *d = *s;
        }
        Value {
            bytes,
            len: data.len().min(4),
        }
    }

    fn as_slice(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or(&[])
    }

    const fn len(&self) -> usize {
        self.len
    }
}

/// A download in progress (values are at most 4 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Pending {
    key: (u16, u8),
    buf: [u8; 4],
    len: usize,
}

/// The values of a CiA 418 battery module's objects (see the module docs
/// for the table). The application sets the fields it measures; the
/// charger writes the `rw` ones through SDO or RPDOs.
///
/// ```
/// use canopen_codec::cia418::{BatteryObjects, Temperature};
/// use canopen_codec::od::ObjectDictionary;
/// use canopen_codec::NodeId;
/// let mut od = BatteryObjects::new(NodeId::new(1).unwrap(), "BMS");
/// od.temperature = Temperature::from_celsius(25).unwrap();
/// let mut buf = [0u8; 2];
/// assert_eq!(od.read(0x6010, 0, 0, &mut buf), Ok(2));
/// assert_eq!(buf, [0xC8, 0x00]); // 200 * 0.125 degC
/// assert!(od.info(0x6010, 0).unwrap().pdo_mappable);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BatteryObjects {
    node: NodeId,
    /// 1000h device type (bits 16-19: optional PDOs).
    pub device_type: DeviceType,
    /// 1001h error register.
    pub error_register: ErrorRegister,
    /// 1008h manufacturer device name.
    pub device_name: &'static str,
    /// 1017h producer heartbeat time in ms.
    pub heartbeat_time_ms: u16,
    /// 1018h identity.
    pub identity: Identity,
    /// 6000h battery status.
    pub battery_status: BatteryStatus,
    /// 6001h charger status (written by the charger).
    pub charger_status: ChargerStatus,
    /// 6010h temperature.
    pub temperature: Temperature,
    /// 6020h battery parameters.
    pub battery_parameters: BatteryParameters,
    /// 6050h cumulative total Ah charge.
    pub cumulative_total_ah_charge: AmpHours,
    /// 6051h Ah expended since last charge.
    pub ah_expended_since_last_charge: EighthAmpHours,
    /// 6052h Ah returned during last charge (rw).
    pub ah_returned_during_last_charge: EighthAmpHours,
    /// 6053h Ah since last equalization (rw).
    pub ah_since_last_equalization: EighthAmpHours,
    /// 6054h date of last equalization (rw).
    pub date_of_last_equalization: EqualizationDate,
    /// 6060h battery voltage.
    pub battery_voltage: BatteryVoltage,
    /// 6070h charge current requested.
    pub charge_current_requested: ChargeCurrentRequested,
    /// 6080h charger state of charge (written by the charger; default FFh).
    pub charger_state_of_charge: StateOfCharge,
    /// 6081h battery state of charge (default FFh, invalid).
    pub battery_state_of_charge: StateOfCharge,
    /// 6090h water level status.
    pub water_level: WaterLevelStatus,
    /// 6030h, 6031h, 6040h, 6041h in [`PackedStringObject::ALL`] order.
    packed: [PackedValue; 4],
    pending: Option<Pending>,
}

const fn v8(v: u8) -> Value {
    Value {
        bytes: [v, 0, 0, 0],
        len: 1,
    }
}
const fn v16(v: u16) -> Value {
    let [a, b] = v.to_le_bytes();
    Value {
        bytes: [a, b, 0, 0],
        len: 2,
    }
}
const fn v32(v: u32) -> Value {
    Value {
        bytes: v.to_le_bytes(),
        len: 4,
    }
}

fn packed_slot(object: PackedStringObject) -> usize {
    match object {
        PackedStringObject::BatterySerialNumber => 0,
        PackedStringObject::BatteryId => 1,
        PackedStringObject::VehicleSerialNumber => 2,
        PackedStringObject::VehicleId => 3,
    }
}

impl BatteryObjects {
    /// The objects of module `node` named `device_name` (1008h): device
    /// type 418 with no optional PDOs, heartbeat 1000 ms, everything else
    /// zero except the two states of charge (FFh, invalid), the charge
    /// current requested (FFFFh, invalid) and the packed strings (empty,
    /// one element).
    #[must_use]
    pub const fn new(node: NodeId, device_name: &'static str) -> Self {
        BatteryObjects {
            node,
            device_type: DeviceType::cia418(0),
            error_register: ErrorRegister::empty(),
            device_name,
            heartbeat_time_ms: 1000,
            identity: Identity {
                vendor_id: 0,
                product_code: 0,
                revision_number: 0,
                serial_number: 0,
            },
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
            pending: None,
        }
    }

    /// The node id (1200h values).
    #[must_use]
    pub const fn node(&self) -> NodeId {
        self.node
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

    /// Forgets a download in progress (the module's resets).
    pub(crate) fn abort_pending(&mut self) {
        self.pending = None;
    }

    /// True if the dictionary has object `index` (any sub-index).
    #[must_use]
    pub fn has_object(index: u16) -> bool {
        BATTERY_OBJECT_INDEXES.contains(&index)
    }

    /// Access, current value and PDO-mappability of every object but 1008h.
    fn entry(&self, index: u16, sub: u8) -> Result<(Access, Value, bool), AbortCode> {
        use Access::{Const, ReadOnly as Ro, ReadWrite as Rw};
        let node = u32::from(self.node.raw());
        let found = match (index, sub) {
            (DEVICE_TYPE, 0) => (Const, v32(self.device_type.raw()), false),
            (ERROR_REGISTER, 0) => (Ro, v8(self.error_register.bits()), false),
            (PRODUCER_HEARTBEAT_TIME, 0) => (Rw, v16(self.heartbeat_time_ms), false),
            (IDENTITY, 0) => (Ro, v8(Identity::HIGHEST_SUB_INDEX), false),
            (IDENTITY, s) if self.identity.sub(s).is_some() => {
                (Ro, v32(self.identity.sub(s).unwrap_or(0)), false)
            }
            (SDO_SERVER_PARAMETER, 0) => (Ro, v8(2), false),
            (SDO_SERVER_PARAMETER, 1) => (Ro, v32(u32::from(SDO_RX_BASE) + node), false),
            (SDO_SERVER_PARAMETER, 2) => (Ro, v32(u32::from(SDO_TX_BASE) + node), false),
            (BATTERY_STATUS, 0) => (Ro, v8(self.battery_status.bits()), true),
            (CHARGER_STATUS, 0) => (Rw, v8(self.charger_status.bits()), true),
            (TEMPERATURE, 0) => (Ro, v16(self.temperature.raw() as u16), true),
            (BATTERY_PARAMETERS, s) if s <= BatteryParameters::HIGHEST_SUB_INDEX => {
                let bytes = self.battery_parameters.encode_sub(s).unwrap_or_default();
                (Ro, Value::from_slice(bytes.as_slice()), false)
            }
            (CUMULATIVE_TOTAL_AH_CHARGE, 0) => {
                (Ro, v32(self.cumulative_total_ah_charge.raw()), false)
            }
            (AH_EXPENDED_SINCE_LAST_CHARGE, 0) => {
                (Ro, v16(self.ah_expended_since_last_charge.raw()), false)
            }
            (AH_RETURNED_DURING_LAST_CHARGE, 0) => {
                (Rw, v16(self.ah_returned_during_last_charge.raw()), true)
            }
            (AH_SINCE_LAST_EQUALIZATION, 0) => {
                (Rw, v16(self.ah_since_last_equalization.raw()), false)
            }
            (DATE_OF_LAST_EQUALIZATION, 0) => (Ro, v8(EqualizationDate::NUMBER_OF_ELEMENTS), false),
            (DATE_OF_LAST_EQUALIZATION, EqualizationDate::SUB_MINUTES) => {
                (Rw, v16(self.date_of_last_equalization.minutes), false)
            }
            (DATE_OF_LAST_EQUALIZATION, EqualizationDate::SUB_DAYS) => {
                (Rw, v16(self.date_of_last_equalization.days), false)
            }
            (BATTERY_VOLTAGE, 0) => (Ro, v32(self.battery_voltage.raw()), true),
            (CHARGE_CURRENT_REQUESTED, 0) => (Ro, v16(self.charge_current_requested.raw()), true),
            (CHARGER_STATE_OF_CHARGE, 0) => (Rw, v8(self.charger_state_of_charge.raw()), true),
            (BATTERY_STATE_OF_CHARGE, 0) => (Ro, v8(self.battery_state_of_charge.raw()), true),
            (WATER_LEVEL_STATUS, 0) => (Ro, v8(self.water_level.bits()), false),
            (i, s) => {
                let Some(object) = PackedStringObject::from_index(i) else {
                    return Err(if Self::has_object(i) {
                        AbortCode::SubIndexDoesNotExist
                    } else {
                        AbortCode::ObjectDoesNotExist
                    });
                };
                let v = self
                    .packed
                    .get(packed_slot(object))
                    .copied()
                    .unwrap_or(PackedValue::EMPTY);
                if s == 0 {
                    (Ro, v8(v.count), false)
                } else {
                    let word = v.word(s).ok_or(AbortCode::SubIndexDoesNotExist)?;
                    (Ro, v32(word), false)
                }
            }
        };
        Ok(found)
    }

    /// Applies a complete, length-checked write.
    fn apply(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        match (index, sub, data) {
            (PRODUCER_HEARTBEAT_TIME, 0, &[a, b]) => {
                self.heartbeat_time_ms = u16::from_le_bytes([a, b]);
            }
            (CHARGER_STATUS, 0, &[a]) => self.charger_status = ChargerStatus::from_bits_retain(a),
            (AH_RETURNED_DURING_LAST_CHARGE, 0, &[a, b]) => {
                self.ah_returned_during_last_charge =
                    EighthAmpHours::from_raw(u16::from_le_bytes([a, b]));
            }
            (AH_SINCE_LAST_EQUALIZATION, 0, &[a, b]) => {
                self.ah_since_last_equalization =
                    EighthAmpHours::from_raw(u16::from_le_bytes([a, b]));
            }
            (DATE_OF_LAST_EQUALIZATION, EqualizationDate::SUB_MINUTES, &[a, b]) => {
                let minutes = u16::from_le_bytes([a, b]);
                if minutes >= 1440 {
                    return Err(AbortCode::ValueTooHigh);
                }
                self.date_of_last_equalization.minutes = minutes;
            }
            (DATE_OF_LAST_EQUALIZATION, EqualizationDate::SUB_DAYS, &[a, b]) => {
                self.date_of_last_equalization.days = u16::from_le_bytes([a, b]);
            }
            (CHARGER_STATE_OF_CHARGE, 0, &[a]) => {
                let soc = StateOfCharge::from_raw(a);
                if soc.is_out_of_range() {
                    return Err(AbortCode::ValueTooHigh);
                }
                self.charger_state_of_charge = soc;
            }
            _ => return Err(AbortCode::WriteOfReadOnlyObject),
        }
        Ok(())
    }
}

impl ObjectDictionary for BatteryObjects {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        if index == MANUFACTURER_DEVICE_NAME {
            return match sub {
                0 => Ok(ObjectInfo::fixed(Access::Const, self.device_name.len())),
                _ => Err(AbortCode::SubIndexDoesNotExist),
            };
        }
        let (access, value, mappable) = self.entry(index, sub)?;
        let info = ObjectInfo::fixed(access, value.len());
        Ok(if mappable { info.mappable() } else { info })
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let value;
        let bytes: &[u8] = if index == MANUFACTURER_DEVICE_NAME {
            if sub != 0 {
                return Err(AbortCode::SubIndexDoesNotExist);
            }
            self.device_name.as_bytes()
        } else {
            value = self.entry(index, sub)?.1;
            value.as_slice()
        };
        let src = bytes.get(offset..).unwrap_or(&[]);
        let mut n = 0;
        for (d, s) in buf.iter_mut().zip(src) {
            *d = *s;
            n += 1;
        }
        Ok(n)
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        let info = self.info(index, sub)?;
        if !info.access.is_writable() {
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        let (mut buf, len) = match self.pending {
            Some(p) if p.key == (index, sub) && offset > 0 => (p.buf, p.len),
            _ => ([0u8; 4], 0),
        };
        let end = len.saturating_add(data.len());
        if offset != len || end > buf.len() {
            self.pending = None;
            return Err(AbortCode::DataTypeLengthTooHigh);
        }
        for (d, s) in buf.iter_mut().skip(len).zip(data) {
            *d = *s;
        }
        self.pending = Some(Pending {
            key: (index, sub),
            buf,
            len: end,
        });
        Ok(())
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let (buf, got) = match self.pending.take() {
            Some(p) if p.key == (index, sub) => (p.buf, p.len),
            _ => ([0u8; 4], 0),
        };
        let info = self.info(index, sub)?;
        if !info.access.is_writable() {
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        let got = got.min(len);
        info.check_download_len(got)?;
        self.apply(index, sub, buf.get(..got).unwrap_or(&[]))
    }

    fn abort_write(&mut self, index: u16, sub: u8) {
        let _ = (index, sub);
        self.pending = None;
    }
}

#[cfg(test)]
#[path = "objects_tests.rs"]
mod tests;
