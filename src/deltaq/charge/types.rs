//! The charge control's configuration, inputs, outputs and events.

use core::time::Duration;

use super::algorithm::{ChargeAlgorithm, EXAMPLE_ALGORITHMS};
use crate::deltaq::{DeltaQCode, DerateReasons, ExtendedChargeStatus, ExternalOverride};

/// The configuration of [`ChargeControl`](super::ChargeControl).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargeConfig {
    /// The charger's algorithms (2241h selects among them by id).
    pub algorithms: &'static [ChargeAlgorithm],
    /// The permanent algorithm at power-on (None: E-0-2-0 until 2241h).
    pub permanent_algorithm: Option<u16>,
    /// Local mode without CAN after the hold-off: this algorithm (None: the
    /// active one).
    pub no_can_algorithm: Option<u16>,
    /// How long local mode waits for a BMS before charging on its own.
    pub can_hold_off: Duration,
    /// The rest (output off) between absorption and float or complete.
    pub rest: Duration,
    /// The charger's maximum output current, mA.
    pub max_current_ma: u32,
    /// The charger's maximum output voltage, mV; the voltage request starts here.
    pub max_voltage_mv: u32,
    /// The charger's maximum output power, W.
    pub max_power_w: u32,
    /// An output voltage at least this high means a battery is connected, mV.
    pub battery_detect_mv: u32,
    /// Charger temperature where derating starts, degC.
    pub derate_start_c: i16,
    /// Charger temperature where the current reaches zero, degC.
    pub derate_stop_c: i16,
    /// AC input below this (RMS, mV) is no AC: the charger stops as on a
    /// mains loss (ours: the IC Series' rated input starts at 85 VAC).
    pub ac_min_mv: u32,
    /// AC input above this (RMS, mV) raises E-0-2-3 "high AC voltage"
    /// (Delta-Q section 4.4.1: ">270 VAC") and stops the output.
    pub ac_max_mv: u32,
}

impl ChargeConfig {
    /// Our 1.5 kW, 48 V example charger (the ICL1500's class: up to 25 A,
    /// 72 V) with [`EXAMPLE_ALGORITHMS`]: permanent
    /// algorithm 1 (flooded lead acid), no-CAN algorithm 1, a 10 s CAN
    /// hold-off, 60 s rest, battery detected from 12 V, derating from 70 to
    /// 90 degC, AC from 85 V to 270 V RMS.
    #[must_use]
    pub const fn example() -> Self {
        ChargeConfig {
            algorithms: &EXAMPLE_ALGORITHMS,
            permanent_algorithm: Some(1),
            no_can_algorithm: Some(1),
            can_hold_off: Duration::from_secs(10),
            rest: Duration::from_secs(60),
            max_current_ma: 25_000,
            max_voltage_mv: 72_000,
            max_power_w: 1500,
            battery_detect_mv: 12_000,
            derate_start_c: 70,
            derate_stop_c: 90,
            ac_min_mv: 85_000,
            ac_max_mv: 270_000,
        }
    }

    /// The algorithm `id` of the table.
    #[must_use]
    pub fn algorithm(&self, id: u16) -> Option<&'static ChargeAlgorithm> {
        self.algorithms.iter().find(|a| a.id == id)
    }
}

/// What the power stage measures: what a real charger's input and output
/// stages read (Delta-Q IC Series CANopen interface specification rev 2.0,
/// section 4.4.1: the alarms and faults raised from these readings, and
/// section 5: 2200h AC voltage, 2101h battery voltage, 2002h current).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PowerStage {
    /// AC (mains) input voltage, RMS, mV (0: no AC). Below
    /// [`ChargeConfig::ac_min_mv`] the charger takes AC as absent; above
    /// [`ChargeConfig::ac_max_mv`] it raises E-0-2-3 "high AC voltage".
    pub ac_mv: u32,
    /// Output (battery) voltage at the terminals, mV, signed: negative
    /// when a battery is connected the wrong way round (E-0-1-2 "reverse
    /// polarity").
    pub voltage_mv: i32,
    /// Output current, mA.
    pub current_ma: u32,
    /// The charger's temperature, degC.
    pub temperature_c: i16,
    /// The hardware faults the stage's own monitoring reports (F-0-0-1 to
    /// F-0-0-6).
    pub faults: StageFaults,
}

impl PowerStage {
    /// No AC, nothing on the output, 25 degC, no fault.
    pub const OFF: PowerStage = PowerStage {
        ac_mv: 0,
        voltage_mv: 0,
        current_ma: 0,
        temperature_c: 25,
        faults: StageFaults::empty(),
    };

    /// The nominal AC input of our example charger, 230 V RMS, mV.
    pub const AC_NOMINAL_MV: u32 = 230_000;

    /// The output voltage as a battery connected the right way round
    /// gives it, mV (0 for a reversed one).
    #[must_use]
    pub const fn battery_mv(&self) -> u32 {
        if self.voltage_mv > 0 {
            self.voltage_mv.unsigned_abs()
        } else {
            0
        }
    }
}

impl StageFaults {
    /// The Delta-Q fault code of a single flag (F-0-0-1 for
    /// [`OUTPUT_STAGE`](Self::OUTPUT_STAGE), ...); `None` for no flag or
    /// several.
    #[must_use]
    pub const fn code(self) -> Option<DeltaQCode> {
        if self.bits().count_ones() == 1 {
            Some(DeltaQCode::Fault(self.bits().trailing_zeros() as u8 + 1))
        } else {
            None
        }
    }

    /// The flag of a fault's name, as a scenario or a bench names it:
    /// `output-stage`, `input-stage`, `input-stage-2`,
    /// `current-measurement`, `relay`, `output-current`, or its Delta-Q
    /// label (`F-0-0-1` ...).
    #[must_use]
    pub fn from_label(name: &str) -> Option<Self> {
        const NAMES: [(&str, &str, StageFaults); 6] = [
            ("output-stage", "F-0-0-1", StageFaults::OUTPUT_STAGE),
            ("input-stage", "F-0-0-2", StageFaults::INPUT_STAGE),
            ("input-stage-2", "F-0-0-3", StageFaults::INPUT_STAGE_2),
            (
                "current-measurement",
                "F-0-0-4",
                StageFaults::CURRENT_MEASUREMENT,
            ),
            ("relay", "F-0-0-5", StageFaults::RELAY),
            ("output-current", "F-0-0-6", StageFaults::OUTPUT_CURRENT),
        ];
        NAMES
            .iter()
            .find(|(n, l, _)| name.eq_ignore_ascii_case(n) || name.eq_ignore_ascii_case(l))
            .map(|(_, _, f)| *f)
    }
}

/// What the bus says (the charger's objects and its supervision).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusInputs {
    /// The battery module's heartbeat is present.
    pub battery_present: bool,
    /// 6000h battery status (bit 0: ready to charge).
    pub battery_status: u8,
    /// 6070h charge current requested (1/16 A; FFFFh invalid).
    pub current_request: u16,
    /// The voltage request of 2271h / 2276h (the one written last), mV.
    pub voltage_request_mv: u32,
    /// 4201h external override.
    pub external_override: ExternalOverride,
    /// The Ah target ([`AH_TARGET`](super::AH_TARGET), Q3 Ah; FFFFh none).
    pub ah_target: u16,
    /// 6081h battery state of charge (%; FFh invalid).
    pub battery_soc: u8,
    /// The CAN controller reports a bus error (error passive or bus off).
    pub bus_error: bool,
    /// 6010h battery temperature as the module reports it (1/8 degC),
    /// read while the module is present (E-0-0-8).
    pub battery_temperature: i16,
}

impl BusInputs {
    /// Nothing on the bus: no module, no request, the voltage request at
    /// `max_voltage_mv`.
    #[must_use]
    pub const fn none(max_voltage_mv: u32) -> Self {
        BusInputs {
            battery_present: false,
            battery_status: 0,
            current_request: 0xFFFF,
            voltage_request_mv: max_voltage_mv,
            external_override: ExternalOverride::empty(),
            ah_target: 0xFFFF,
            battery_soc: 0xFF,
            bus_error: false,
            battery_temperature: 25 * 8,
        }
    }
}

/// The power stage's orders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SetPoints {
    /// Output on.
    pub enabled: bool,
    /// Current limit, mA (0 when off).
    pub current_ma: u32,
    /// Voltage limit, mV (0 when off).
    pub voltage_mv: u32,
}

/// Where the charge stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ChargePhase {
    /// No charge: no AC, no battery, or (remote) a condition missing.
    Idle,
    /// Local mode: waiting the CAN hold-off for a BMS.
    HoldOff,
    /// Constant current.
    Bulk,
    /// Constant voltage; the current tapers.
    Absorption,
    /// Equalize (lead acid), at the algorithm's equalize voltage.
    Equalize,
    /// Output off between absorption and float or complete.
    Rest,
    /// Maintenance at the float voltage.
    Float,
    /// The cycle is complete; output off.
    Complete,
    /// Remote mode: delivering the BMS's request.
    Remote,
    /// The BMS (6000h) or a module EMCY ended the charge.
    Terminated,
}

impl ChargePhase {
    /// The phase in words.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ChargePhase::Idle => "idle",
            ChargePhase::HoldOff => "CAN hold-off",
            ChargePhase::Bulk => "bulk (constant current)",
            ChargePhase::Absorption => "absorption (constant voltage)",
            ChargePhase::Equalize => "equalize",
            ChargePhase::Rest => "rest",
            ChargePhase::Float => "float",
            ChargePhase::Complete => "complete",
            ChargePhase::Remote => "remote (BMS request)",
            ChargePhase::Terminated => "terminated",
        }
    }

    /// The phases in which the charger delivers current.
    #[must_use]
    pub const fn delivers(self) -> bool {
        matches!(
            self,
            ChargePhase::Bulk
                | ChargePhase::Absorption
                | ChargePhase::Equalize
                | ChargePhase::Float
                | ChargePhase::Remote
        )
    }
}

impl core::fmt::Display for ChargePhase {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// The power stage's faults and the charge control's alarms, one row per
/// flag (Delta-Q IC Series CANopen interface specification rev 2.0,
/// section 4.4.1): each fault row declares its flag of [`StageFaults`]
/// (bit `n`, fault F-0-0-(`n`+1)) and, `as`, its flag of [`ChargeAlarms`]
/// (bit [`FAULT_SHIFT`] + `n`); each alarm row its flag of
/// [`ChargeAlarms`] with its code. [`ALARM_CODES`], the code of each
/// [`ChargeAlarms`] bit, follows from the rows; a row out of bit order
/// fails to compile.
macro_rules! alarm_flags {
    (
        $(#[$faults_meta:meta])*
        pub struct StageFaults: u8 {
            $($(#[doc = $fault_doc:literal])* const $stage:ident = 1 << $fault_bit:literal, as $fault:ident;)*
        }
        $(#[$alarms_meta:meta])*
        pub struct ChargeAlarms: u32 {
            $($(#[doc = $alarm_doc:literal])* const $alarm:ident = 1 << $alarm_bit:literal, code $code:ident($n:literal);)*
        }
    ) => {
        bitflags::bitflags! {
            $(#[$faults_meta])*
            pub struct StageFaults: u8 {
                $($(#[doc = $fault_doc])* const $stage = 1 << $fault_bit;)*
            }
        }

        bitflags::bitflags! {
            $(#[$alarms_meta])*
            pub struct ChargeAlarms: u32 {
                $($(#[doc = $alarm_doc])* const $alarm = 1 << $alarm_bit;)*
                $($(#[doc = $fault_doc])* const $fault = 1 << (FAULT_SHIFT + $fault_bit);)*
            }
        }

        /// The bit of the first [`ChargeAlarms`] fault flag (F-0-0-1): the
        /// fault flags follow the alarms.
        const FAULT_SHIFT: u32 = [$($alarm_bit),*].len() as u32;

        /// The Delta-Q code of each [`ChargeAlarms`] flag, by bit (section
        /// 4.4.1): the alarms' codes, then F-0-0-1 to F-0-0-6.
        pub const ALARM_CODES: [DeltaQCode; [$($alarm_bit,)* $($fault_bit,)*].len()] = [
            $(DeltaQCode::$code($n),)*
            $(DeltaQCode::Fault($fault_bit + 1),)*
        ];

        // Each list's row `n` is its flag bit `n`.
        const _: () = {
            let mut alarms: &[u32] = &[$($alarm_bit),*];
            let mut bit = 0;
            while let [first, rest @ ..] = alarms {
                assert!(*first == bit, "alarm rows in bit order");
                (alarms, bit) = (rest, bit + 1);
            }
            let mut faults: &[u8] = &[$($fault_bit),*];
            let mut bit = 0;
            while let [first, rest @ ..] = faults {
                assert!(*first == bit, "fault rows in bit order");
                (faults, bit) = (rest, bit + 1);
            }
        };
    };
}

alarm_flags! {
    /// The power stage's hardware faults (Delta-Q IC Series CANopen
    /// interface specification rev 2.0, section 4.4.1, faults F-0-0-1 to
    /// F-0-0-6, EEC 5000h "CANopen device hardware"): flag bit `n` is
    /// fault F-0-0-(`n`+1). Any of them turns the output off while it
    /// stands.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct StageFaults: u8 {
        /// F-0-0-1 output stage error.
        const OUTPUT_STAGE = 1 << 0, as FAULT_OUTPUT_STAGE;
        /// F-0-0-2 input stage error.
        const INPUT_STAGE = 1 << 1, as FAULT_INPUT_STAGE;
        /// F-0-0-3 input stage error (the document's second input stage
        /// code; ours: the input stage's second monitor, e.g. its PFC bus).
        const INPUT_STAGE_2 = 1 << 2, as FAULT_INPUT_STAGE_2;
        /// F-0-0-4 current measurement error.
        const CURRENT_MEASUREMENT = 1 << 3, as FAULT_CURRENT_MEASUREMENT;
        /// F-0-0-5 DC output relay test error (high voltage across the
        /// closed relay).
        const RELAY = 1 << 4, as FAULT_RELAY;
        /// F-0-0-6 output current error.
        const OUTPUT_CURRENT = 1 << 5, as FAULT_OUTPUT_CURRENT;
    }

    /// The alarms and faults [`ChargeControl`](super::ChargeControl)
    /// raises, each a Delta-Q code (Delta-Q IC Series CANopen interface
    /// specification rev 2.0, section 4.4.1; flag bit `n` is
    /// [`ALARM_CODES`]`[n]`): the alarms, then the power stage's faults
    /// ([`StageFaults`] from bit 16). What raises and clears each is in
    /// the [protections](super#protections).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct ChargeAlarms: u32 {
        /// E-0-0-1 battery high voltage.
        const HIGH_VOLTAGE = 1 << 0, code Alarm(1);
        /// E-0-2-0 active algorithm not set.
        const ALGORITHM_NOT_SET = 1 << 1, code Alarm(20);
        /// E-0-2-8 incompatible algorithm.
        const INCOMPATIBLE_ALGORITHM = 1 << 2, code Alarm(28);
        /// E-0-2-9 CAN-bus communication error.
        const BUS_ERROR = 1 << 3, code Alarm(29);
        /// E-0-4-5 battery disconnected.
        const BATTERY_DISCONNECTED = 1 << 4, code Alarm(45);
        /// E-0-0-2 battery low voltage.
        const LOW_VOLTAGE = 1 << 5, code Alarm(2);
        /// E-0-0-3 charge timeout (the safety timer).
        const CHARGE_TIMEOUT = 1 << 6, code Alarm(3);
        /// E-0-0-4 battery could not meet minimum voltage.
        const MINIMUM_VOLTAGE = 1 << 7, code Alarm(4);
        /// E-0-0-7 battery amp-hour limit exceeded.
        const AH_LIMIT = 1 << 8, code Alarm(7);
        /// E-0-0-8 battery temperature out of range.
        const TEMPERATURE = 1 << 9, code Alarm(8);
        /// E-0-1-2 reverse polarity.
        const REVERSE_POLARITY = 1 << 10, code Alarm(12);
        /// E-0-1-3 battery does not take current.
        const NO_CURRENT = 1 << 11, code Alarm(13);
        /// E-0-1-4 number of cells invalid.
        const CELLS_INVALID = 1 << 12, code Alarm(14);
        /// E-0-2-3 high AC voltage.
        const HIGH_AC = 1 << 13, code Alarm(23);
        /// E-0-2-5 low AC voltage oscillation.
        const AC_OSCILLATION = 1 << 14, code Alarm(25);
        /// E-0-3-6 battery temperature sensor (the module's EMCY 5010h).
        const TEMPERATURE_SENSOR = 1 << 15, code Alarm(36);
    }
}

impl ChargeAlarms {
    /// The faults F-0-0-1 to F-0-0-6.
    pub const FAULTS: ChargeAlarms = ChargeAlarms::from_bits_retain(0x3F << FAULT_SHIFT);

    /// What stops the output while it stands: every alarm and fault but
    /// E-0-2-0 and E-0-2-8 (no algorithm: nothing runs anyway), E-0-2-9
    /// (local mode charges on without the bus; remote mode stops by its
    /// own rule) and E-0-3-6 (the charge goes on at half current).
    pub const STOPS_OUTPUT: ChargeAlarms = ChargeAlarms::all()
        .difference(ChargeAlarms::ALGORITHM_NOT_SET)
        .difference(ChargeAlarms::INCOMPATIBLE_ALGORITHM)
        .difference(ChargeAlarms::BUS_ERROR)
        .difference(ChargeAlarms::TEMPERATURE_SENSOR);

    /// The fault flags of the power stage's `faults`.
    #[must_use]
    pub const fn of_faults(faults: StageFaults) -> ChargeAlarms {
        ChargeAlarms::from_bits_retain((faults.bits() as u32) << FAULT_SHIFT)
    }

    /// The Delta-Q code of a single flag (section 4.4.1); for several, the
    /// lowest one's, and for none, [`DeltaQCode::NONE`].
    #[must_use]
    pub const fn code(self) -> DeltaQCode {
        let bit = self.bits().trailing_zeros() as usize;
        if bit < ALARM_CODES.len() {
            ALARM_CODES[bit]
        } else {
            DeltaQCode::NONE
        }
    }

    /// The one to display (2060h): the first fault, else the first alarm.
    #[must_use]
    pub const fn displayed(self) -> ChargeAlarms {
        let faults = self.intersection(ChargeAlarms::FAULTS);
        let from = if faults.is_empty() { self } else { faults };
        ChargeAlarms::from_bits_retain(from.bits() & from.bits().wrapping_neg())
    }
}

/// What [`ChargeControl`](super::ChargeControl) reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ChargeEvent {
    /// The phase changed.
    Phase {
        /// Before.
        from: ChargePhase,
        /// Now.
        to: ChargePhase,
    },
    /// An alarm was raised (`active`) or cleared.
    Alarm {
        /// The alarm (one flag).
        alarm: ChargeAlarms,
        /// Raised or cleared.
        active: bool,
    },
}

/// The status objects, as the charger reports them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargeStatus {
    /// 2006h extended charge status.
    pub extended: ExtendedChargeStatus,
    /// 6001h charger status (bit 0: delivering, able to charge).
    pub charger_status: u8,
    /// 2008h derate reasons.
    pub derate: DerateReasons,
    /// 6052h Ah returned during this charge (Q3 Ah).
    pub ah_returned: u16,
    /// 6080h charger state of charge (%; FFh unknown).
    pub charger_soc: u8,
    /// Time since the cycle started ([`ELAPSED_TIME`](super::ELAPSED_TIME)).
    pub elapsed: Duration,
}
