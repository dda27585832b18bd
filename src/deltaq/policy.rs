//! The charger's reaction to the battery module's emergencies; the rules and
//! the choices are in the parent module's docs.

use core::fmt;

use crate::emcy::{Emergency, ErrorCode};

/// How the charger is configured to work with CANopen (document section 3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum OperatingMode {
    /// Remote control: an external BMS starts, stops and controls charging;
    /// the charger needs it present.
    Remote,
    /// Local: the charger runs the charge cycle itself; a BMS may monitor it
    /// and may override it.
    Local,
    /// Local override (application note 740-0024): local mode with the BMS
    /// overriding. Reacts to emergencies as [`OperatingMode::Local`].
    LocalOverride,
    /// Monitoring only: other CANopen devices just watch the charging
    /// parameters. Never changes the charge on an emergency.
    MonitoringOnly,
}

impl OperatingMode {
    /// All four modes, in declaration order.
    pub const ALL: [OperatingMode; 4] = [
        OperatingMode::Remote,
        OperatingMode::Local,
        OperatingMode::LocalOverride,
        OperatingMode::MonitoringOnly,
    ];

    /// True for the modes in which the charger itself runs the charge cycle
    /// (local and local override).
    #[must_use]
    pub const fn is_local(self) -> bool {
        matches!(self, OperatingMode::Local | OperatingMode::LocalOverride)
    }

    /// The mode's name: `remote`, `local`, `local override`, `monitoring only`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            OperatingMode::Remote => "remote",
            OperatingMode::Local => "local",
            OperatingMode::LocalOverride => "local override",
            OperatingMode::MonitoringOnly => "monitoring only",
        }
    }
}

impl fmt::Display for OperatingMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the charger does on a battery module's emergency.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reaction {
    /// Carry on (log the code only).
    Continue,
    /// Local mode: end the charge cycle.
    TerminateCharging,
    /// Remote mode: shut down.
    ShutDown,
    /// The CiA 418 temperature-sensor-fault handling (EEC 5010h). The
    /// document's description of it is missing; the caller supplies it.
    TemperatureSensorFault,
}

impl Reaction {
    /// True for the reactions that end the charge: `TerminateCharging` and
    /// `ShutDown`. (`TemperatureSensorFault` is left to the caller.)
    #[must_use]
    pub const fn stops_charging(self) -> bool {
        matches!(self, Reaction::TerminateCharging | Reaction::ShutDown)
    }
}

/// The charger's reaction, in `mode`, to an emergency with error code `eec`
/// from the battery module (rules and choices in the
/// [`deltaq` module docs](crate::deltaq)).
///
/// ```
/// use canopen_codec::deltaq::{emcy_reaction, OperatingMode, Reaction};
/// use canopen_codec::emcy::ErrorCode;
///
/// assert_eq!(emcy_reaction(OperatingMode::Local, ErrorCode::HEARTBEAT), Reaction::Continue);
/// assert_eq!(emcy_reaction(OperatingMode::Local, ErrorCode::GENERIC), Reaction::TerminateCharging);
/// assert_eq!(emcy_reaction(OperatingMode::Remote, ErrorCode::HEARTBEAT), Reaction::ShutDown);
/// assert_eq!(
///     emcy_reaction(OperatingMode::Remote, ErrorCode::TEMPERATURE_SENSOR_FAULT),
///     Reaction::TemperatureSensorFault
/// );
/// assert_eq!(emcy_reaction(OperatingMode::Remote, ErrorCode::NO_ERROR), Reaction::Continue);
/// ```
#[must_use]
pub const fn emcy_reaction(mode: OperatingMode, eec: ErrorCode) -> Reaction {
    if eec.is_reset() {
        return Reaction::Continue;
    }
    match mode {
        OperatingMode::MonitoringOnly => Reaction::Continue,
        _ if eec.0 == ErrorCode::TEMPERATURE_SENSOR_FAULT.0 => Reaction::TemperatureSensorFault,
        OperatingMode::Remote => Reaction::ShutDown,
        OperatingMode::Local | OperatingMode::LocalOverride => {
            if eec.0 & 0xF000 == 0x8000 {
                Reaction::Continue
            } else {
                Reaction::TerminateCharging
            }
        }
    }
}

/// [`emcy_reaction`] for a whole EMCY message (only its error code counts).
#[must_use]
pub const fn emergency_reaction(mode: OperatingMode, emcy: &Emergency) -> Reaction {
    emcy_reaction(mode, emcy.code)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::Codec;
    use OperatingMode::{Local, LocalOverride, MonitoringOnly, Remote};
    use Reaction::{Continue, ShutDown, TemperatureSensorFault, TerminateCharging};

    /// (EEC, remote, local, local override, monitoring only).
    #[rustfmt::skip]
    const TABLE: &[(u16, Reaction, Reaction, Reaction, Reaction)] = &[
        // Error reset / no error (00xxh).
        (0x0000, Continue, Continue, Continue, Continue),
        (0x0001, Continue, Continue, Continue, Continue),
        (0x00FF, Continue, Continue, Continue, Continue),
        // Temperature sensor fault, CiA 418.
        (0x5010, TemperatureSensorFault, TemperatureSensorFault, TemperatureSensorFault, Continue),
        // Its neighbours are ordinary codes.
        (0x5000, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x5011, ShutDown, TerminateCharging, TerminateCharging, Continue),
        // 8xxxh monitoring: local mode continues.
        (0x8000, ShutDown, Continue, Continue, Continue),
        (0x8110, ShutDown, Continue, Continue, Continue),
        (0x8130, ShutDown, Continue, Continue, Continue),
        (0x8210, ShutDown, Continue, Continue, Continue),
        (0x8FFF, ShutDown, Continue, Continue, Continue),
        // Everything else.
        (0x0100, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x1000, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x2310, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x3100, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x4210, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x6000, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x7FFF, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0x9000, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0xA000, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0xF000, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0xFF00, ShutDown, TerminateCharging, TerminateCharging, Continue),
        (0xFFFF, ShutDown, TerminateCharging, TerminateCharging, Continue),
    ];

    #[test]
    fn reaction_table() {
        for &(eec, remote, local, local_override, monitoring) in TABLE {
            let eec = ErrorCode(eec);
            assert_eq!(emcy_reaction(Remote, eec), remote, "remote {eec}");
            assert_eq!(emcy_reaction(Local, eec), local, "local {eec}");
            assert_eq!(
                emcy_reaction(LocalOverride, eec),
                local_override,
                "local override {eec}"
            );
            assert_eq!(
                emcy_reaction(MonitoringOnly, eec),
                monitoring,
                "monitoring {eec}"
            );
        }
    }

    #[test]
    fn every_code_in_every_mode() {
        for raw in 0..=u16::MAX {
            let eec = ErrorCode(raw);
            let reset = raw >> 8 == 0;
            let temp = raw == 0x5010;
            let monitoring_class = raw >> 12 == 0x8;
            let expect_remote = match (reset, temp) {
                (true, _) => Continue,
                (_, true) => TemperatureSensorFault,
                _ => ShutDown,
            };
            let expect_local = match (reset, temp, monitoring_class) {
                (true, _, _) | (_, _, true) => Continue,
                (_, true, _) => TemperatureSensorFault,
                _ => TerminateCharging,
            };
            assert_eq!(emcy_reaction(Remote, eec), expect_remote);
            assert_eq!(emcy_reaction(Local, eec), expect_local);
            assert_eq!(emcy_reaction(LocalOverride, eec), expect_local);
            assert_eq!(emcy_reaction(MonitoringOnly, eec), Continue);
        }
    }

    #[test]
    fn from_emergency_frames() {
        // The capture's heartbeat-lost EMCY, as if a module had sent it.
        let e = Emergency::parse(&[0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]).unwrap();
        assert_eq!(emergency_reaction(Local, &e), Continue);
        assert_eq!(emergency_reaction(Remote, &e), ShutDown);
        let reset = Emergency::parse(&[0; 8]).unwrap();
        for mode in OperatingMode::ALL {
            assert_eq!(emergency_reaction(mode, &reset), Continue);
        }
    }

    #[test]
    fn helpers() {
        assert!(Local.is_local() && LocalOverride.is_local());
        assert!(!Remote.is_local() && !MonitoringOnly.is_local());
        assert_eq!(format!("{LocalOverride}"), "local override");
        assert_eq!(format!("{MonitoringOnly}"), "monitoring only");
        assert!(ShutDown.stops_charging() && TerminateCharging.stops_charging());
        assert!(!Continue.stops_charging() && !TemperatureSensorFault.stops_charging());
    }
}
