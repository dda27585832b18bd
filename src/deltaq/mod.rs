//! Delta-Q IC Series charger: alarm and fault table, the 1003h byte-order
//! quirk, manufacturer objects and the EMCY-consumer reaction policy.
//!
//! Sources: "Delta-Q IC Series CANopen interface specification rev 2.0"
//! (CANopen interface 2.6, 2018), cited by its own section numbers, and
//! Delta-Q's published object list (its EDS; rev 2.0 moved the object
//! descriptions there). Two errata of the document are corrected where they
//! are used: the F-0-0-6 1003h value (below) and the 2100h scale
//! ([`BatteryVoltageLegacy`]).
//!
//! - [`DeltaQCode`], [`ALARMS_AND_FAULTS`]: the charger's alarm ("E-0-x-y")
//!   and fault ("F-0-x-y") codes, decoded from its EMCY frames
//!   (little-endian) and from objects 1003h / 2060h (byte-swapped high word).
//!   The F-0-0-6 erratum (`0x500006C0` printed for `0x06C05000`) is handled by
//!   [`DeltaQCode::from_error_field_lenient`].
//! - [`emcy_reaction`]: what the charger does when the battery module sends
//!   an emergency, per [`OperatingMode`].
//! - [`index`]: the manufacturer object indexes; [`ExtendedChargeStatus`],
//!   the scaled values ([`ChargingCurrent`], [`BatteryVoltage`], ...) and
//!   the other object types, with "no value" sentinels as `None`.
//! - [`timeouts`]: the recommended timeouts.
//! - [`device_type`]: Delta-Q's reading of the battery module's 1000h bits
//!   (bit 20: the module wants the charger's TPDO 3).
//! - [`CHARGER_DEFAULT_PDOS`]: the charger's default PDO set, and
//!   [`default_mapping_for_cob_id`] for a bus of charger and module.
//! - [`CHARGER_CATALOGUE`], [`DELTAQ_OBJECTS`]: the charger's objects for
//!   decoding PDO fields in words.
//!
//! ```
//! use canopen_codec::deltaq::{emcy_reaction, DeltaQCode, OperatingMode, Reaction};
//! use canopen_codec::emcy::Emergency;
//! use canopen_codec::wire::Codec;
//!
//! // The capture's EMCY 08A#3081012080000000.
//! let e = Emergency::parse(&[0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]).unwrap();
//! let code = DeltaQCode::from_emergency(&e);
//! assert_eq!(format!("{code}: {}", code.description().unwrap()), "E-0-3-2: heartbeat lost");
//! // Had a battery module sent this EEC (8130h), a local-mode charger carries on:
//! assert_eq!(emcy_reaction(OperatingMode::Local, e.code), Reaction::Continue);
//! ```
//!
//! ## Alarm and fault codes (document section 4.4.1)
//!
//! A Delta-Q code is 16 bits: prefix | number. Alarms ("E-0-x-y", user
//! recoverable) have prefix 8000h, faults ("F-0-x-y", charger hardware) C000h,
//! and the number is the decimal `x*10 + y` (E-0-2-1 is 21 = 0x15, code 8015h).
//!
//! **Byte-order quirk.** The charger puts the code in the first two
//! manufacturer-specific bytes of its EMCY frame *little-endian* (EMCY bytes 3-4),
//! but in object 1003h (and 2060h) the code sits in the high word of the
//! Unsigned32 with its bytes *swapped*. E-0-0-1 (8001h) with EEC 9000h:
//!
//! - EMCY data: `00 90 <ER> 01 80 00 00 00`
//! - 1003h value `0x0180_9000`, on the SDO wire (little-endian) `00 90 80 01`
//!
//! ```
//! use canopen_codec::deltaq::DeltaQCode;
//! use canopen_codec::emcy::{Emergency, ErrorCode, ErrorRegister};
//! use canopen_codec::wire::Codec;
//!
//! let e = Emergency::parse(&[0x00, 0x90, 0x01, 0x01, 0x80, 0, 0, 0]).unwrap();
//! let code = DeltaQCode::from_emergency(&e);
//! assert_eq!(code, DeltaQCode::Alarm(1));
//! assert_eq!(format!("{code}"), "E-0-0-1");
//! assert_eq!(DeltaQCode::from_error_field(0x0180_9000), (ErrorCode::EXTERNAL, code));
//! assert_eq!(code.to_error_field(ErrorCode::EXTERNAL), 0x0180_9000);
//! assert_eq!(code.to_emergency(ErrorCode::EXTERNAL, ErrorRegister::GENERIC), e);
//! ```
//!
//! **Erratum, F-0-0-6.** The document prints the 1003h value of F-0-0-6 as
//! `0x500006C0`: the two words are swapped. The correct value, following the
//! rule every other row obeys, is `0x06C0_5000`. [`DeltaQCode::from_error_field`]
//! decodes strictly: the erratum value gives EEC 06C0h and `Other(0x0050)`.
//! [`DeltaQCode::from_error_field_lenient`] also accepts the word-swapped form
//! when (and only when) the swap yields a table entry whose EEC matches.
//!
//! ## EMCY consumer policy (document sections 3.1 and 4.4.2)
//!
//! The document's rules, as [`emcy_reaction`] applies them:
//!
//! | EEC received | Remote | Local, LocalOverride | MonitoringOnly |
//! |---|---|---|---|
//! | 00xxh (error reset / no error) | `Continue` | `Continue` | `Continue` |
//! | 5010h (temperature sensor fault) | `TemperatureSensorFault` | `TemperatureSensorFault` | `Continue` |
//! | 8xxxh (monitoring: communication, protocol) | `ShutDown` | `Continue` | `Continue` |
//! | any other code | `ShutDown` | `TerminateCharging` | `Continue` |
//!
//! Choices where the document is silent (each documented on the item):
//!
//! - **00xxh** is CiA 301's "error reset or no error" class: a module that
//!   clears its errors is not reporting one, so every mode continues. (The
//!   document's "any error code" is read as "any error".)
//! - **5010h** gets its own reaction kind in both local and remote mode; the
//!   section describing it is missing from the document ("Error! Reference
//!   source not found"), so the caller decides what
//!   [`Reaction::TemperatureSensorFault`] means. Only the exact code 5010h
//!   triggers it, not the error register's device-profile bit.
//! - **Local override** is local mode in which the BMS overrides parts of the
//!   charge cycle (application note 740-0024, not public): the charger still
//!   owns the cycle, so it reacts as in local mode.
//! - **Monitoring only**: the bus only watches the charger; the document gives
//!   the consumer rules for local and remote mode only, so a monitoring-only
//!   charger does not change its charge on a module's emergency (not even on
//!   5010h). The code is still logged by the caller.
//!
//! Every received code is to be logged, whatever the reaction; that is the
//! caller's job.
//!
//! ## Object values (Delta-Q's object list)
//!
//! Scaled values keep the raw integer ([`raw`](ChargingCurrent::raw)); unit
//! accessors convert it: `as_f32` / `as_f64` (exact in `f64`; exact in `f32`
//! for the 16-bit types) and milli-unit integers rounded to the nearest
//! milli-unit, halves up (exact where the step divides 1/1000, as for
//! [`ChargerAhReturned`]). `Qn` means `n` fractional bits: the value is
//! `raw / 2^n` units.
//!
//! **No value.** 0xFFFF (16-bit) and 0xFFFF_FFFF (32-bit) mean "no value" for
//! every scaled type and for [`AlgorithmRequest`]; `from_raw` / `decode` give
//! `None` for them and `encode_raw` / `encode` write them back for `None`.
//! A value never holds the sentinel, so `Some(v)` always encodes to a real
//! reading.
//!
//! ```
//! use canopen_codec::deltaq::{BatteryVoltage, ChargingCurrent, ExtendedChargeStatus};
//!
//! // The capture's charger TPDO 0, 18A#7413454E70000000 (remapped by its
//! // integrator: 2002h, 2101h, 2006h, 16 bits padding).
//! let data = [0x74, 0x13, 0x45, 0x4E, 0x70, 0x00, 0x00, 0x00];
//! let current = ChargingCurrent::decode(&data[0..2]).unwrap().unwrap();
//! assert_eq!(current.milliamps(), 19_453); // 0x1374 / 256 A
//! let volts = BatteryVoltage::decode(&data[2..4]).unwrap().unwrap();
//! assert_eq!(volts.millivolts(), 78_270); // 0x4E45 / 256 V
//! let status = ExtendedChargeStatus::decode(&data[4..6]).unwrap();
//! assert_eq!(status.to_u16(), 0x0070);
//! ```

mod catalogue;
pub mod charge;
// The charger supervises its battery module with the device core's
// heartbeat consumer (feature `heartbeat-consumer`).
#[cfg(feature = "heartbeat-consumer")]
mod charger;
mod charger_objects;
mod codes;
pub mod device_type;
#[cfg(all(feature = "alloc", feature = "heartbeat-consumer"))]
mod eds;
mod formats;
mod objects;
mod pdo;
mod policy;

pub use catalogue::{CHARGER_CATALOGUE, DELTAQ_UNSERVED_OBJECTS};
#[cfg(feature = "heartbeat-consumer")]
pub use charger::{
    Charger, ChargerAppDictionary, ChargerConfig, ChargerDevice, ChargerEvent, ChargerPowerOn,
    ChargerProfile,
};
pub use charger_objects::{
    ChargerDictionary, ChargerObjects, ChargerPowerOnValues, CHARGER_PARAMETERS_RESTORED,
    DELTAQ_OBJECTS,
};
pub use codes::{AlarmFaultEntry, DeltaQCode, ALARMS_AND_FAULTS};
#[cfg(all(feature = "alloc", feature = "heartbeat-consumer"))]
pub use eds::charger_eds;
pub use formats::{
    ALGORITHM_REQUEST_FORMAT, DERATE_REASONS_FLAGS, DISPLAYED_ERROR_FORMAT,
    EXTENDED_CHARGE_STATUS_FLAGS, EXTERNAL_OVERRIDE_FLAGS,
};
pub use objects::{
    AcVoltage, AlgorithmRequest, BatteryVoltage, BatteryVoltageLegacy, ChargeIndication,
    ChargeStatusFlags, ChargeType, ChargerAhReturned, ChargingCurrent, DerateReasons,
    DisplayedError, ExtendedChargeStatus, ExternalOverride, OverrideSource, VoltageRequest,
    VoltageRequest16,
};
pub use pdo::{
    charger_default_mapping, charger_default_pdo, default_mapping_for_cob_id, paired_module_pdo,
    CHARGER_DEFAULT_PDOS,
};
pub use policy::{emcy_reaction, emergency_reaction, OperatingMode, Reaction};

/// Delta-Q Technologies' CANopen vendor ID, the value of 1018h sub 1
/// (identity object, vendor-ID) in its chargers, as Delta-Q's published
/// object list (the IQ3K3 charger's EDS: `VendorNumber=0x00000110` and
/// 1018h sub 1 `DefaultValue=0x00000110`) gives it. A log or EDS that shows
/// this vendor ID is evidence that a node is a Delta-Q device.
pub const VENDOR_ID: u32 = 0x0000_0110;

/// Object dictionary indexes of the Delta-Q charger's manufacturer objects
/// (Delta-Q's published object list), plus 6052h whose scaling the charger
/// fixes.
pub mod index {
    /// 2002h charging current, U16 Q8 A ([`ChargingCurrent`](super::ChargingCurrent)).
    pub const CHARGING_CURRENT: u16 = 0x2002;
    /// 2006h extended charge status, U16
    /// ([`ExtendedChargeStatus`](super::ExtendedChargeStatus)).
    pub const EXTENDED_CHARGE_STATUS: u16 = 0x2006;
    /// 2008h derate reasons, U8 ([`DerateReasons`](super::DerateReasons)).
    pub const DERATE_REASONS: u16 = 0x2008;
    /// 2060h current displayed error / fault, U32
    /// ([`DisplayedError`](super::DisplayedError)).
    pub const DISPLAYED_ERROR: u16 = 0x2060;
    /// 2100h battery voltage (legacy), U16 Q10 V
    /// ([`BatteryVoltageLegacy`](super::BatteryVoltageLegacy)).
    pub const BATTERY_VOLTAGE_LEGACY: u16 = 0x2100;
    /// 2101h battery voltage, U16 Q8 V ([`BatteryVoltage`](super::BatteryVoltage)).
    pub const BATTERY_VOLTAGE: u16 = 0x2101;
    /// 2200h AC voltage, U16 Q4 V ([`AcVoltage`](super::AcVoltage)).
    pub const AC_VOLTAGE: u16 = 0x2200;
    /// 2241h active algorithm request, U32
    /// ([`AlgorithmRequest`](super::AlgorithmRequest)).
    pub const ALGORITHM_REQUEST: u16 = 0x2241;
    /// 2271h voltage request, U32 Q10 V ([`VoltageRequest`](super::VoltageRequest)).
    pub const VOLTAGE_REQUEST: u16 = 0x2271;
    /// 2275h cable resistance, U8 mOhm, not PDO-mappable.
    pub const CABLE_RESISTANCE: u16 = 0x2275;
    /// 2276h voltage request (16 bit), U16 Q8 V
    /// ([`VoltageRequest16`](super::VoltageRequest16)).
    pub const VOLTAGE_REQUEST_16: u16 = 0x2276;
    /// 2500h cumulative counters, ARRAY of U32, non-volatile.
    pub const CUMULATIVE_COUNTERS: u16 = 0x2500;
    /// Highest sub-index of 2500h (sub 1..=12h).
    pub const CUMULATIVE_COUNTERS_LAST_SUB: u8 = 0x12;
    /// 2E00h charge history record index, U16.
    pub const CHARGE_HISTORY_INDEX: u16 = 0x2E00;
    /// 2E01h charge history records, DOMAIN (layout not published).
    pub const CHARGE_HISTORY_RECORDS: u16 = 0x2E01;
    /// 2FFAh padding, U8 at sub 1 and 2: zero-fill for PDO padding.
    pub const PADDING: u16 = 0x2FFA;
    /// 4000h reset request, U16, write-only (trigger value not published).
    pub const RESET_REQUEST: u16 = 0x4000;
    /// 4201h external override, U8 ([`ExternalOverride`](super::ExternalOverride)).
    pub const EXTERNAL_OVERRIDE: u16 = 0x4201;
    /// 6052h Ah returned during the last charge; on the charger U16 Q3 Ah,
    /// 0xFFFF = no value ([`ChargerAhReturned`](super::ChargerAhReturned)).
    pub const AH_RETURNED: u16 = crate::cia418::AH_RETURNED_DURING_LAST_CHARGE;
}

/// Delta-Q's recommended timeouts and periods, in milliseconds ("Delta-Q IC
/// Series CANopen interface specification rev 2.0", section 4.3.1, Table 1,
/// and section 4.5.5 for the TPDO periods). The charger does not support
/// SYNC.
pub mod timeouts {
    /// Boot-up: 5000 ms.
    pub const BOOT_UP_MS: u64 = 5000;
    /// NMT: 2000 ms.
    pub const NMT_MS: u64 = 2000;
    /// SDO: 2000 ms.
    pub const SDO_MS: u64 = 2000;
    /// Objects 1010h / 1011h (store / restore parameters): 2000 ms.
    pub const STORE_RESTORE_MS: u64 = 2000;
    /// The charger's heartbeat producer period (1017h): 1000 ms.
    pub const HEARTBEAT_PRODUCER_MS: u64 = 1000;
    /// The charger's heartbeat consumer timeout for the battery module
    /// (1016h): 2000 ms.
    pub const HEARTBEAT_CONSUMER_MS: u64 = 2000;
    /// Transmit period of the charger's TPDO 0, 1 and 2: 200 ms.
    pub const CHARGER_TPDO_0_2_PERIOD_MS: u64 = 200;
    /// Transmit period of the charger's TPDO 3: 1000 ms.
    pub const CHARGER_TPDO_3_PERIOD_MS: u64 = 1000;
    /// The battery module's default TPDO event timer (1800h..1802h sub 5):
    /// 200 ms.
    pub const BATTERY_TPDO_EVENT_TIMER_MS: u64 = 200;
}
