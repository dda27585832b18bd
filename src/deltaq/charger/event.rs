//! What the charger reports ([`ChargerEvent`]), apart to keep the
//! charger's module short.

use crate::abort::AbortCode;
use crate::deltaq::charge::{BatteryIdentity, ChargeEvent};
use crate::deltaq::Reaction;
use crate::device::DeviceEvent;
use crate::emcy::Emergency;
use crate::nmt::NmtState;

/// What the charger reports.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum ChargerEvent {
    /// An event of the device core (NMT, SDO, RPDOs, heartbeats, resets).
    Device(DeviceEvent),
    /// The battery module was heard (first heartbeat, boot-up, or back after a loss).
    BatteryFound {
        /// The state it reports.
        state: NmtState,
    },
    /// The battery module's heartbeat was lost (E-0-3-2).
    BatteryLost,
    /// No battery heartbeat for at least 2000 ms (at least the consumer
    /// time, when that is longer): the module is taken as gone (E-0-3-0);
    /// an operational charger left operational for pre-operational.
    BatteryGone,
    /// The PDOs are paired and configured; `tpdos` / `rpdos` say which (bit n = PDO n).
    Configured {
        /// Charger TPDOs in use.
        tpdos: u8,
        /// Charger RPDOs in use.
        rpdos: u8,
    },
    /// Reading the module's configuration failed.
    ConfigurationFailed {
        /// Object read.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Abort code.
        code: AbortCode,
    },
    /// 1000h does not name profile 418.
    NotABatteryModule {
        /// The module's 1000h.
        device_type: u32,
    },
    /// The module sent an EMCY; `reaction` is the policy's answer (the
    /// charge control acts on it).
    BatteryEmcy {
        /// The emergency.
        emcy: Emergency,
        /// What the charger does.
        reaction: Reaction,
    },
    /// The charge control changed phase or raised or cleared an alarm
    /// (each alarm also goes out as a Delta-Q EMCY).
    Charge(ChargeEvent),
    /// The module described its battery in 6020h (sub 1 type, sub 2 Ah
    /// capacity, sub 4 cells); `algorithm`
    /// is the one now active (`None`: the table has none for it).
    BatteryIdentified {
        /// What the module said.
        battery: BatteryIdentity,
        /// The active algorithm after the choice.
        algorithm: Option<u16>,
    },
    /// Reading 6020h failed (the module aborted, or did not answer within
    /// the SDO timeout): the charger keeps its default algorithm.
    IdentificationFailed {
        /// The sub-index whose read failed.
        sub: u8,
        /// The abort code received or sent.
        code: AbortCode,
    },
}

impl From<DeviceEvent> for ChargerEvent {
    fn from(e: DeviceEvent) -> Self {
        ChargerEvent::Device(e)
    }
}
