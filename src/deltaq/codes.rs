//! Delta-Q alarm and fault codes and their table; see the parent module's
//! docs for the byte-order quirk and the F-0-0-6 erratum.

use core::fmt;

use crate::emcy::{Emergency, ErrorCode, ErrorFieldEntry, ErrorRegister};

/// Prefix (high byte) of an alarm code, "E-0-x-y".
const ALARM_PREFIX: u16 = 0x8000;
/// Prefix (high byte) of a fault code, "F-0-x-y".
const FAULT_PREFIX: u16 = 0xC000;

/// A Delta-Q alarm or fault code, as carried in the charger's EMCY frames and
/// in objects 1003h / 2060h.
///
/// Every `u16` maps to exactly one canonical value ([`DeltaQCode::from_raw`]):
/// a high byte of 80h is an alarm, C0h a fault, anything else `Other`. The
/// number of an alarm or fault is its low byte (`x*10 + y` for the labels the
/// charger displays). [`DeltaQCode::raw`] gives the value back, so
/// `from_raw(c.raw())` round-trips every `u16`.
///
/// `Other(raw)` is meant for values outside both ranges (`Other(0)` is what
/// an error-reset EMCY carries). Building `Other` with an alarm or fault
/// pattern by hand (`Other(0x8001)`) gives a non-canonical value that
/// compares unequal to `Alarm(1)` although [`raw`](DeltaQCode::raw) agrees;
/// [`canonical`](DeltaQCode::canonical) normalises it.
///
/// [`Display`](fmt::Display) writes the charger's label (see there); no
/// allocation. The byte-order quirk of EMCY versus 1003h and the F-0-0-6
/// erratum are described in the [`deltaq` module docs](crate::deltaq).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DeltaQCode {
    /// An alarm, "E-0-x-y": code `0x8000 | n`, `n = x*10 + y`.
    Alarm(u8),
    /// A fault, "F-0-x-y": code `0xC000 | n`, `n = x*10 + y`.
    Fault(u8),
    /// Any other 16-bit value, kept raw.
    Other(u16),
}

impl DeltaQCode {
    /// No Delta-Q code: what an error-reset EMCY (`00 00 00 00 00 00 00 00`)
    /// and an empty 2060h carry.
    pub const NONE: DeltaQCode = DeltaQCode::Other(0);
    /// E-0-2-9, CAN-bus communication error (EEC 9000h).
    pub const CAN_BUS_COMMUNICATION: DeltaQCode = DeltaQCode::Alarm(29);
    /// E-0-3-0, battery module communication error (EEC 8130h).
    pub const BATTERY_MODULE_COMMUNICATION: DeltaQCode = DeltaQCode::Alarm(30);
    /// E-0-3-2, heartbeat lost (EEC 8130h).
    pub const HEARTBEAT_LOST: DeltaQCode = DeltaQCode::Alarm(32);
    /// E-0-4-2, CAN configuration error (EEC 6000h): the charger raises it
    /// when the module's 1000h does not name profile 418.
    pub const CAN_CONFIGURATION: DeltaQCode = DeltaQCode::Alarm(42);
    /// E-0-4-3, PDO CRC error (EEC 9000h).
    pub const PDO_CRC: DeltaQCode = DeltaQCode::Alarm(43);
    /// E-0-4-4, PDO sequence count error (EEC 9000h).
    pub const PDO_SEQUENCE_COUNT: DeltaQCode = DeltaQCode::Alarm(44);
    /// E-0-4-5, battery disconnected (EEC 9000h).
    pub const BATTERY_DISCONNECTED: DeltaQCode = DeltaQCode::Alarm(45);
    /// E-0-4-6, invalid PDO length (EEC 8210h).
    pub const INVALID_PDO_LENGTH: DeltaQCode = DeltaQCode::Alarm(46);

    /// The code for a 16-bit value: high byte 80h is an alarm, C0h a fault,
    /// anything else `Other`. Total.
    #[must_use]
    pub const fn from_raw(raw: u16) -> Self {
        match raw & 0xFF00 {
            ALARM_PREFIX => DeltaQCode::Alarm(raw as u8),
            FAULT_PREFIX => DeltaQCode::Fault(raw as u8),
            _ => DeltaQCode::Other(raw),
        }
    }

    /// The 16-bit value (`0x8000 | n`, `0xC000 | n` or the raw `Other`).
    #[must_use]
    pub const fn raw(self) -> u16 {
        match self {
            DeltaQCode::Alarm(n) => ALARM_PREFIX | n as u16,
            DeltaQCode::Fault(n) => FAULT_PREFIX | n as u16,
            DeltaQCode::Other(raw) => raw,
        }
    }

    /// `from_raw(self.raw())`: turns a hand-built `Other(0x80nn)` or
    /// `Other(0xC0nn)` into the `Alarm` / `Fault` it stands for.
    #[must_use]
    pub const fn canonical(self) -> Self {
        Self::from_raw(self.raw())
    }

    /// The alarm "E-0-x-y", if `x` and `y` are decimal digits (`0..=9`).
    #[must_use]
    pub const fn alarm(x: u8, y: u8) -> Option<Self> {
        match two_digits(x, y) {
            Some(n) => Some(DeltaQCode::Alarm(n)),
            None => None,
        }
    }

    /// The fault "F-0-x-y", if `x` and `y` are decimal digits (`0..=9`).
    #[must_use]
    pub const fn fault(x: u8, y: u8) -> Option<Self> {
        match two_digits(x, y) {
            Some(n) => Some(DeltaQCode::Fault(n)),
            None => None,
        }
    }

    /// True for an alarm (high byte 80h).
    #[must_use]
    pub const fn is_alarm(self) -> bool {
        self.raw() & 0xFF00 == ALARM_PREFIX
    }

    /// True for a fault (high byte C0h).
    #[must_use]
    pub const fn is_fault(self) -> bool {
        self.raw() & 0xFF00 == FAULT_PREFIX
    }

    /// The label's parts `(letter, x, y)`: `('E', 3, 2)` for E-0-3-2,
    /// `('F', 0, 6)` for F-0-0-6. `None` for `Other` and for alarm or fault
    /// numbers above 99, which have no "x-y" label.
    #[must_use]
    pub const fn label_parts(self) -> Option<(char, u8, u8)> {
        let (letter, n) = match self.canonical() {
            DeltaQCode::Alarm(n) => ('E', n),
            DeltaQCode::Fault(n) => ('F', n),
            DeltaQCode::Other(_) => return None,
        };
        if n <= 99 {
            Some((letter, n / 10, n % 10))
        } else {
            None
        }
    }

    /// Parses a label "E-0-x-y" / "F-0-x-y" (x, y one decimal digit each;
    /// upper-case letter). Anything else is `None`. The inverse of
    /// [`Display`](fmt::Display) for labelled codes.
    #[must_use]
    pub fn from_label(label: &str) -> Option<Self> {
        let [letter, b'-', b'0', b'-', x, b'-', y] = *label.as_bytes() else {
            return None;
        };
        let (x, y) = (x.wrapping_sub(b'0'), y.wrapping_sub(b'0'));
        match letter {
            b'E' => Self::alarm(x, y),
            b'F' => Self::fault(x, y),
            _ => None,
        }
    }

    /// The row of [`ALARMS_AND_FAULTS`] for this code, if it is listed.
    #[must_use]
    pub fn entry(self) -> Option<&'static AlarmFaultEntry> {
        let raw = self.raw();
        ALARMS_AND_FAULTS.iter().find(|e| e.code.raw() == raw)
    }

    /// The table's description of this code, if it is listed.
    #[must_use]
    pub fn description(self) -> Option<&'static str> {
        self.entry().map(|e| e.description)
    }

    /// The code a charger EMCY carries: manufacturer bytes 0-1 (EMCY data
    /// bytes 3-4), little-endian. The other three manufacturer bytes are
    /// ignored. An error-reset EMCY gives [`DeltaQCode::NONE`].
    #[must_use]
    pub fn from_emergency(e: &Emergency) -> Self {
        let [m0, m1, ..] = e.manufacturer;
        Self::from_raw(u16::from_le_bytes([m0, m1]))
    }

    /// The EMCY the charger sends for this code: `eec`, `register`, and the
    /// code little-endian in manufacturer bytes 0-1; bytes 2-4 zero.
    #[must_use]
    pub fn to_emergency(self, eec: ErrorCode, register: ErrorRegister) -> Emergency {
        let [lo, hi] = self.raw().to_le_bytes();
        Emergency {
            code: eec,
            register,
            manufacturer: [lo, hi, 0, 0, 0],
        }
    }

    /// Splits a 1003h or 2060h Unsigned32: low word the EEC, high word the
    /// Delta-Q code with its bytes swapped (`0x0180_9000` is EEC 9000h and
    /// code 8001h). Strict and total: see
    /// [`from_error_field_lenient`](Self::from_error_field_lenient) for the
    /// F-0-0-6 erratum.
    #[must_use]
    pub const fn from_error_field(value: u32) -> (ErrorCode, Self) {
        let entry = ErrorFieldEntry::from_u32(value);
        (entry.code, Self::from_error_field_entry(entry))
    }

    /// Like [`from_error_field`](Self::from_error_field), but also accepts
    /// the word-swapped layout the document prints for F-0-0-6
    /// (`0x500006C0`: high word EEC, low word code byte-swapped).
    ///
    /// The swapped reading is taken only if the strict reading is not a
    /// table entry *and* the swapped reading is a table entry whose EEC
    /// matches; every other value decodes exactly as the strict function
    /// does. So `0x500006C0` gives (5000h, F-0-0-6), while every correct
    /// 1003h value keeps its strict meaning.
    #[must_use]
    pub fn from_error_field_lenient(value: u32) -> (ErrorCode, Self) {
        let strict = Self::from_error_field(value);
        if strict.1.entry().is_some() {
            return strict;
        }
        let (eec, code) = Self::from_error_field(value.rotate_left(16));
        match code.entry() {
            Some(row) if row.eec == eec => (eec, code),
            _ => strict,
        }
    }

    /// The 1003h / 2060h Unsigned32 for this code with `eec`: the code's bytes
    /// swapped in the high word, `eec` in the low word.
    #[must_use]
    pub const fn to_error_field(self, eec: ErrorCode) -> u32 {
        self.to_error_field_entry(eec).to_u32()
    }

    /// The code in a 1003h entry already split by [`ErrorFieldEntry`] (its
    /// `info` word, bytes swapped).
    #[must_use]
    pub const fn from_error_field_entry(entry: ErrorFieldEntry) -> Self {
        Self::from_raw(entry.info.swap_bytes())
    }

    /// The [`ErrorFieldEntry`] for this code with `eec`.
    #[must_use]
    pub const fn to_error_field_entry(self, eec: ErrorCode) -> ErrorFieldEntry {
        ErrorFieldEntry {
            code: eec,
            info: self.raw().swap_bytes(),
        }
    }
}

impl Default for DeltaQCode {
    /// [`DeltaQCode::NONE`].
    fn default() -> Self {
        DeltaQCode::NONE
    }
}

/// The number `xy` of the label "E-0-x-y" / "F-0-x-y", if both are decimal
/// digits.
const fn two_digits(x: u8, y: u8) -> Option<u8> {
    if x <= 9 && y <= 9 {
        Some(x * 10 + y)
    } else {
        None
    }
}

crate::bytes::raw_word!(DeltaQCode: u16, DeltaQCode::from_raw, DeltaQCode::raw);

impl fmt::Display for DeltaQCode {
    /// The charger's label for alarm and fault numbers 0..=99, whether or not
    /// the table lists them: `E-0-3-2`, `F-0-0-6`, `E-0-0-5`. Every other
    /// value (an `Other`, or an alarm / fault number 100..=255) is the raw
    /// code as `0x` and four upper-case hex digits: `0x0000`, `0x1234`,
    /// `0x80A5`. A hand-built non-canonical `Other(0x8020)` displays as its
    /// canonical form, `E-0-3-2`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.label_parts() {
            Some((letter, x, y)) => write!(f, "{letter}-0-{x}-{y}"),
            None => write!(f, "0x{:04X}", self.raw()),
        }
    }
}

/// One row of the Delta-Q alarm and fault table ("Delta-Q IC Series CANopen
/// interface specification rev 2.0", section 4.4.1). Rows the document groups ("E-0-0-1, E-0-2-1")
/// are separate rows here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlarmFaultEntry {
    /// The Delta-Q code.
    pub code: DeltaQCode,
    /// The charger's label, `"E-0-x-y"` / `"F-0-x-y"` (equal to the code's
    /// `Display`).
    pub label: &'static str,
    /// What the code means (the document's wording, shortened).
    pub description: &'static str,
    /// The CiA 301 emergency error code the charger sends with it.
    pub eec: ErrorCode,
    /// False for the rows marked `*`: they never appear in 1003h, only in
    /// the manufacturer object 2060h (current displayed error).
    pub in_1003h: bool,
}

impl AlarmFaultEntry {
    /// The 1003h / 2060h Unsigned32 of this row (code byte-swapped in the
    /// high word, EEC in the low word).
    #[must_use]
    pub const fn error_field(&self) -> u32 {
        self.code.to_error_field(self.eec)
    }

    /// The EMCY the charger sends for this row with `register`.
    #[must_use]
    pub fn emergency(&self, register: ErrorRegister) -> Emergency {
        self.code.to_emergency(self.eec, register)
    }

    /// True for an alarm row.
    #[must_use]
    pub const fn is_alarm(&self) -> bool {
        self.code.is_alarm()
    }

    /// True for a fault row.
    #[must_use]
    pub const fn is_fault(&self) -> bool {
        self.code.is_fault()
    }
}

const fn row(
    code: DeltaQCode,
    label: &'static str,
    description: &'static str,
    eec: ErrorCode,
    in_1003h: bool,
) -> AlarmFaultEntry {
    AlarmFaultEntry {
        code,
        label,
        description,
        eec,
        in_1003h,
    }
}

use crate::emcy::ErrorCode as E;
use DeltaQCode::{Alarm as A, Fault as F};

/// The complete Delta-Q IC Series alarm and fault table (41 alarms, 6
/// faults), in code order: alarms first, then faults.
///
/// Codes missing from the numbering (E-0-0-5 "charger over temperature" was
/// removed in rev 1.5 because the charger never produces it; E-0-0-6,
/// E-0-0-9 to E-0-1-1 were never listed) are not rows; they still decode
/// and display (`E-0-0-5`) but have no [`entry`](DeltaQCode::entry).
#[rustfmt::skip]
pub const ALARMS_AND_FAULTS: &[AlarmFaultEntry] = &[
    row(A(1), "E-0-0-1", "battery high voltage (threshold from the algorithm)", E::EXTERNAL, true),
    row(A(2), "E-0-0-2", "battery low voltage (threshold from the algorithm)", E::EXTERNAL, true),
    row(A(3), "E-0-0-3", "charge timeout: pack did not reach the required voltage in the safe time limit", E::EXTERNAL, true),
    row(A(4), "E-0-0-4", "battery could not meet minimum voltage", E::EXTERNAL, true),
    row(A(7), "E-0-0-7", "battery amp-hour limit exceeded", E::EXTERNAL, true),
    row(A(8), "E-0-0-8", "battery temperature out of range", E::EXTERNAL, true),
    row(A(12), "E-0-1-2", "reverse polarity", E::EXTERNAL, true),
    row(A(13), "E-0-1-3", "battery does not take current", E::EXTERNAL, true),
    row(A(14), "E-0-1-4", "number of cells invalid", E::GENERIC, true),
    row(A(15), "E-0-1-5", "end-of-charge voltage not in algorithm", E::GENERIC, true),
    row(A(16), "E-0-1-6", "upgrade failed", E::NO_ERROR, false),
    row(A(17), "E-0-1-7", "USB error", E::NO_ERROR, false),
    row(A(18), "E-0-1-8", "storage error", E::NO_ERROR, false),
    row(A(19), "E-0-1-9", "incompatible software", E::NO_ERROR, false),
    row(A(20), "E-0-2-0", "active algorithm not set", E::GENERIC, true),
    row(A(21), "E-0-2-1", "battery high voltage (threshold from the algorithm)", E::EXTERNAL, true),
    row(A(22), "E-0-2-2", "battery low voltage (threshold from the algorithm)", E::EXTERNAL, true),
    row(A(23), "E-0-2-3", "high AC voltage (>270 VAC)", E::EXTERNAL, true),
    row(A(24), "E-0-2-4", "charger failed to initialize", E::GENERIC, true),
    row(A(25), "E-0-2-5", "low AC voltage oscillation", E::EXTERNAL, true),
    row(A(26), "E-0-2-6", "USB script error", E::NO_ERROR, false),
    row(A(27), "E-0-2-7", "USB over current", E::NO_ERROR, false),
    row(A(28), "E-0-2-8", "incompatible algorithm", E::GENERIC, true),
    row(A(29), "E-0-2-9", "CAN-bus communication error", E::EXTERNAL, true),
    row(A(30), "E-0-3-0", "battery module communication error", E::HEARTBEAT, true),
    row(A(31), "E-0-3-1", "reference out of range", E::GENERIC, true),
    row(A(32), "E-0-3-2", "heartbeat lost", E::HEARTBEAT, true),
    row(A(33), "E-0-3-3", "target voltage configuration too high", E::GENERIC, true),
    row(A(34), "E-0-3-4", "battery capacity configuration not set", E::GENERIC, true),
    row(A(35), "E-0-3-5", "target voltage configuration too low", E::GENERIC, true),
    row(A(36), "E-0-3-6", "battery temperature sensor not installed", E::EXTERNAL, true),
    row(A(37), "E-0-3-7", "CAN download failed", E::DEVICE_SOFTWARE, true),
    row(A(38), "E-0-3-8", "fan error", E::EXTERNAL, true),
    row(A(39), "E-0-3-9", "button stuck down", E::GENERIC, true),
    row(A(40), "E-0-4-0", "fan supply voltage low", E::GENERIC, true),
    row(A(41), "E-0-4-1", "software internal error", E::DEVICE_SOFTWARE, true),
    row(A(42), "E-0-4-2", "CAN configuration error", E::DEVICE_SOFTWARE, true),
    row(A(43), "E-0-4-3", "PDO CRC error", E::EXTERNAL, true),
    row(A(44), "E-0-4-4", "PDO sequence count error", E::EXTERNAL, true),
    row(A(45), "E-0-4-5", "battery disconnected", E::EXTERNAL, true),
    row(A(46), "E-0-4-6", "invalid PDO length", E::PDO_LENGTH, true),
    row(F(1), "F-0-0-1", "output stage error", E::DEVICE_HARDWARE, true),
    row(F(2), "F-0-0-2", "input stage error", E::DEVICE_HARDWARE, true),
    row(F(3), "F-0-0-3", "input stage error", E::DEVICE_HARDWARE, true),
    row(F(4), "F-0-0-4", "current measurement error", E::DEVICE_HARDWARE, true),
    row(F(5), "F-0-0-5", "DC output relay test error (high voltage across closed relay)", E::DEVICE_HARDWARE, true),
    row(F(6), "F-0-0-6", "output current error", E::DEVICE_HARDWARE, true),
];

#[cfg(test)]
#[path = "codes_tests.rs"]
mod tests;
