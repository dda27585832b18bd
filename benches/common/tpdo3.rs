//! The Delta-Q charger TPDO 3 (2002h/16 charging current, 2100h/16 battery
//! voltage, 2006h/16 extended charge status) as the `pdo` bench and the
//! `pdo_count` harness decode it.

use canopen_codec::deltaq::{BatteryVoltageLegacy, ChargingCurrent, ExtendedChargeStatus};
use canopen_codec::pdo::{MappingEntry, PdoMapping};

/// The TPDO 3 mapping.
pub fn mapping() -> PdoMapping {
    PdoMapping::new(&[
        MappingEntry::new(0x2002, 0, 16),
        MappingEntry::new(0x2100, 0, 16),
        MappingEntry::new(0x2006, 0, 16),
    ])
    .expect("TPDO 3 mapping")
}

/// A TPDO 3 payload (every field has a value).
pub const FRAME: [u8; 6] = [0x74, 0x13, 0x45, 0x4E, 0x70, 0x00];

/// The TPDO 3's three typed values (`None`: "no value").
pub type Values = (
    Option<ChargingCurrent>,
    Option<BatteryVoltageLegacy>,
    ExtendedChargeStatus,
);

/// The TPDO 3 as its typed values.
#[inline]
pub fn decode(m: &PdoMapping, payload: &[u8]) -> Option<Values> {
    let u = m.unpack(payload).ok()?;
    let raw16 = |i| u.raw(i).and_then(|r| u16::try_from(r).ok());
    Some((
        ChargingCurrent::from_raw(raw16(0)?),
        BatteryVoltageLegacy::from_raw(raw16(1)?),
        ExtendedChargeStatus::from_u16(raw16(2)?),
    ))
}
