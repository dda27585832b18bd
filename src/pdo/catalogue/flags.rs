//! Bit-field objects (6000h, 6001h, 6090h, 2006h, 2008h, 4201h) in words.

use core::fmt;

use super::*;

/// The decoded value of a bit-field object; `Display` says it in words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Flags {
    /// 6000h.
    BatteryStatus(BatteryStatus),
    /// 6001h.
    ChargerStatus(ChargerStatus),
    /// 6090h.
    WaterLevelStatus(WaterLevelStatus),
    /// 2006h.
    ExtendedChargeStatus(ExtendedChargeStatus),
    /// 2008h.
    DerateReasons(DerateReasons),
    /// 4201h.
    ExternalOverride(ExternalOverride),
}

impl Flags {
    /// Decodes the raw bits of a `kind` object (excess high bits ignored).
    #[must_use]
    pub const fn from_raw(kind: FlagsKind, raw: u64) -> Self {
        let byte = raw as u8;
        match kind {
            FlagsKind::BatteryStatus => Flags::BatteryStatus(BatteryStatus::from_bits_retain(byte)),
            FlagsKind::ChargerStatus => Flags::ChargerStatus(ChargerStatus::from_bits_retain(byte)),
            FlagsKind::WaterLevelStatus => {
                Flags::WaterLevelStatus(WaterLevelStatus::from_bits_retain(byte))
            }
            FlagsKind::ExtendedChargeStatus => {
                Flags::ExtendedChargeStatus(ExtendedChargeStatus::from_u16(raw as u16))
            }
            FlagsKind::DerateReasons => Flags::DerateReasons(DerateReasons::from_bits_retain(byte)),
            FlagsKind::ExternalOverride => {
                Flags::ExternalOverride(ExternalOverride::from_bits_retain(byte))
            }
        }
    }
}

/// Writes comma-separated items.
struct List<'a, 'b> {
    f: &'a mut fmt::Formatter<'b>,
    empty: bool,
}

impl<'a, 'b> List<'a, 'b> {
    fn new(f: &'a mut fmt::Formatter<'b>) -> Self {
        List { f, empty: true }
    }

    fn item(&mut self, args: fmt::Arguments<'_>) -> fmt::Result {
        if !self.empty {
            self.f.write_str(", ")?;
        }
        self.empty = false;
        self.f.write_fmt(args)
    }

    fn flags(&mut self, set: u8, names: &[(u8, &str)]) -> fmt::Result {
        let mut known = 0u8;
        for &(bit, name) in names {
            known |= bit;
            if set & bit != 0 {
                self.item(format_args!("{name}"))?;
            }
        }
        match set & !known {
            0 => Ok(()),
            rest => self.item(format_args!("other bits {rest:02X}h")),
        }
    }

    fn none_if_empty(&mut self) -> fmt::Result {
        if self.empty {
            self.f.write_str("none")?;
        }
        Ok(())
    }
}

impl fmt::Display for Flags {
    /// `ready to charge`, `AC present, charger enabled, override external
    /// (BMS)`, ...; unknown bits as `other bits 80h`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut l = List::new(f);
        match *self {
            Flags::BatteryStatus(s) => {
                let ready = s.contains(BatteryStatus::READY_TO_CHARGE);
                l.item(format_args!(
                    "{}",
                    if ready {
                        "ready to charge"
                    } else {
                        "not ready to charge"
                    }
                ))?;
                extra(&mut l, s.bits() & !0x01)
            }
            Flags::ChargerStatus(s) => {
                let on = s.contains(ChargerStatus::ENABLED);
                l.item(format_args!(
                    "{}",
                    if on { "enabled" } else { "not enabled" }
                ))?;
                extra(&mut l, s.bits() & !0x01)
            }
            Flags::WaterLevelStatus(s) => {
                l.item(format_args!("{}", if s.is_full() { "full" } else { "low" }))?;
                extra(&mut l, s.bits() & !0x01)
            }
            Flags::ExtendedChargeStatus(s) => {
                l.flags(
                    s.flags.bits(),
                    &[
                        (ChargeStatusFlags::FAULT_ACTIVE.bits(), "fault active"),
                        (ChargeStatusFlags::ALARM_ACTIVE.bits(), "alarm active"),
                        (ChargeStatusFlags::HW_SHUTDOWN.bits(), "hardware shutdown"),
                        (ChargeStatusFlags::DERATING.bits(), "de-rating"),
                        (ChargeStatusFlags::AC_PRESENT.bits(), "AC present"),
                        (ChargeStatusFlags::CHARGER_ENABLED.bits(), "charger enabled"),
                    ],
                )?;
                match s.override_source {
                    OverrideSource::Internal => l.item(format_args!("override internal"))?,
                    OverrideSource::External => l.item(format_args!("override external (BMS)"))?,
                    OverrideSource::Other(v) => l.item(format_args!("override source {v}"))?,
                }
                let indication = match s.indication {
                    ChargeIndication::Inactive => None,
                    ChargeIndication::Below80 => Some("below 80 %"),
                    ChargeIndication::Above80 => Some("above 80 %"),
                    ChargeIndication::Finishing => Some("finishing"),
                    ChargeIndication::Complete => Some("complete"),
                    ChargeIndication::Resting => Some("resting"),
                    ChargeIndication::Equalize => Some("equalize"),
                    ChargeIndication::PowerSupplyMode => Some("power-supply mode"),
                    ChargeIndication::Other(v) => {
                        l.item(format_args!("indication {v}"))?;
                        None
                    }
                };
                if let Some(i) = indication {
                    l.item(format_args!("{i}"))?;
                }
                match s.charge_type {
                    ChargeType::None => Ok(()),
                    ChargeType::Normal => l.item(format_args!("normal charge")),
                    ChargeType::Maintenance => l.item(format_args!("maintenance charge")),
                    ChargeType::Other(v) => l.item(format_args!("charge type {v}")),
                }
            }
            Flags::DerateReasons(s) => {
                l.flags(
                    s.bits(),
                    &[
                        (DerateReasons::AC_VOLTAGE.bits(), "AC voltage"),
                        (DerateReasons::BATTERY_VOLTAGE.bits(), "battery voltage"),
                        (DerateReasons::TEMPERATURE.bits(), "temperature"),
                        (DerateReasons::AC_CURRENT_LIMIT.bits(), "AC current limit"),
                    ],
                )?;
                l.none_if_empty()
            }
            Flags::ExternalOverride(s) => {
                l.flags(
                    s.bits(),
                    &[
                        (ExternalOverride::EQUALIZE.bits(), "equalize"),
                        (ExternalOverride::MAINTENANCE.bits(), "maintenance"),
                    ],
                )?;
                l.none_if_empty()
            }
        }
    }
}

fn extra(l: &mut List<'_, '_>, rest: u8) -> fmt::Result {
    if rest != 0 {
        l.item(format_args!("other bits {rest:02X}h"))?;
    }
    Ok(())
}
