//! The Delta-Q charger's application objects: the CiA 418 objects a CiA
//! 419 charger shares with the battery module (6000h-6081h) and the
//! Delta-Q manufacturer objects (Delta-Q IC Series CANopen interface
//! specification rev 2.0, section 5: 2002h, 2006h, 2060h, 2100h, 2101h,
//! 2200h, 2241h, 2271h, 2276h, 4201h, and the 2FFAh padding objects its
//! PDO mappings use). Fixed storage, no allocation. The communication
//! objects (1000h-1FFFh) are the device core's ([`crate::device`]).

use crate::od::{Access, ObjectDictionary, ObjectInfo, WriteBuffer};
use crate::sdo::AbortCode;

/// The charger's object values. Fields are the application's to read and
/// write; SDO access goes through [`ObjectDictionary`] with the access
/// rights of each object.
#[derive(Debug, Clone, PartialEq, Eq)]
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
    pending: WriteBuffer,
}

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
            pending: WriteBuffer::new(),
        }
    }

    /// Value, access and mappability of a (non-string) object, as up to 4
    /// little-endian bytes.
    fn scalar(&self, index: u16, sub: u8) -> Result<(Access, bool, Bytes), AbortCode> {
        use Access::{Const, ReadOnly as Ro, ReadWrite as Rw};
        let b1 = |v: u8| Bytes::new(&[v]).unwrap_or_default();
        let b2 = |v: u16| Bytes::new(&v.to_le_bytes()).unwrap_or_default();
        let b4 = |v: u32| Bytes::new(&v.to_le_bytes()).unwrap_or_default();
        let one = |s: u8, a, m, v: Bytes| {
            if sub == s {
                Ok((a, m, v))
            } else {
                Err(AbortCode::SubIndexDoesNotExist)
            }
        };
        match index {
            0x6000 => one(0, Rw, true, b1(self.battery_status)),
            0x6001 => one(0, Ro, true, b1(self.charger_status)),
            0x6010 => one(0, Rw, true, b2(self.temperature as u16)),
            0x6052 => one(0, Rw, true, b2(self.ah_returned)),
            0x6060 => one(0, Rw, true, b4(self.battery_voltage)),
            0x6070 => one(0, Rw, true, b2(self.current_requested)),
            0x6080 => one(0, Ro, true, b1(self.charger_soc)),
            0x6081 => one(0, Rw, true, b1(self.battery_soc)),
            0x2002 => one(0, Rw, true, b2(self.charging_current)),
            0x2006 => one(0, Ro, true, b2(self.extended_status)),
            0x2060 => one(0, Ro, true, b4(self.displayed_error)),
            0x2100 => one(0, Ro, true, b2(self.battery_voltage_q10)),
            0x2101 => one(0, Rw, true, b2(self.battery_voltage_q8)),
            0x2200 => one(0, Ro, true, b2(self.ac_voltage)),
            0x2241 => one(0, Rw, true, b4(self.algorithm_request)),
            0x2271 => one(0, Rw, true, b4(self.voltage_request)),
            0x2276 => one(0, Rw, true, b2(self.voltage_request_q8)),
            0x4201 => one(0, Rw, true, b1(self.external_override)),
            0x2FFA => match sub {
                0 => Ok((Const, false, b1(2))),
                1 | 2 => Ok((Rw, true, b1(0))),
                _ => Err(AbortCode::SubIndexDoesNotExist),
            },
            _ => Err(AbortCode::ObjectDoesNotExist),
        }
    }

    fn store(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let u8v = || data.first().copied().unwrap_or(0);
        let u16v = || match *data {
            [a, b] => u16::from_le_bytes([a, b]),
            _ => 0,
        };
        let u32v = || match *data {
            [a, b, c, d] => u32::from_le_bytes([a, b, c, d]),
            _ => 0,
        };
        match (index, sub) {
            (0x6000, 0) => self.battery_status = u8v(),
            (0x6010, 0) => self.temperature = u16v() as i16,
            (0x6052, 0) => self.ah_returned = u16v(),
            (0x6060, 0) => self.battery_voltage = u32v(),
            (0x6070, 0) => self.current_requested = u16v(),
            (0x6081, 0) => self.battery_soc = u8v(),
            (0x2002, 0) => self.charging_current = u16v(),
            (0x2101, 0) => self.battery_voltage_q8 = u16v(),
            (0x2241, 0) => self.algorithm_request = u32v(),
            (0x2271, 0) => self.voltage_request = u32v(),
            (0x2276, 0) => self.voltage_request_q8 = u16v(),
            (0x4201, 0) => self.external_override = u8v(),
            (0x2FFA, 1 | 2) => {}
            _ => return Err(AbortCode::WriteOfReadOnlyObject),
        }
        Ok(())
    }
}

type Bytes = crate::bytes::InlineData<4>;

impl ObjectDictionary for ChargerObjects {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        let (access, mappable, value) = self.scalar(index, sub)?;
        let mut info = ObjectInfo::fixed(access, value.len());
        info.pdo_mappable = mappable;
        Ok(info)
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let (_, _, value) = self.scalar(index, sub)?;
        Ok(crate::od::read_at(value.as_slice(), offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        self.pending.write(index, sub, offset, data)
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let mut pending = self.pending;
        self.pending.clear();
        let data = pending.take(index, sub);
        self.store(index, sub, data.get(..len.min(data.len())).unwrap_or(&[]))
    }

    fn abort_write(&mut self, _: u16, _: u8) {
        self.pending.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_and_access() {
        let mut o = ChargerObjects::new();
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
