//! Emergency error code classes and named codes (CiA 301, emergency error
//! codes table, with the CiA 401 rows CANopenNode ships and CiA 418's 5010h
//! "temperature sensor fault", CiA 418 v1.0.1, 5.3). The names are those
//! CANopenNode's `CO_EMC_*` macros and python-canopen give the same codes.

use super::ErrorCode;

/// The CiA 301 class of an error code: the top-level group its high byte
/// (or high nibble) places it in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ErrorClass {
    /// 00xxh: error reset or no error.
    NoError,
    /// 10xxh: generic error.
    Generic,
    /// 2xxxh: current.
    Current,
    /// 3xxxh: voltage.
    Voltage,
    /// 4xxxh: temperature.
    Temperature,
    /// 50xxh: CANopen device hardware.
    DeviceHardware,
    /// 6xxxh: CANopen device software.
    DeviceSoftware,
    /// 70xxh: additional modules.
    AdditionalModules,
    /// 8xxxh: monitoring (communication, protocol errors).
    Monitoring,
    /// 90xxh: external error.
    External,
    /// F0xxh: additional functions.
    AdditionalFunctions,
    /// FFxxh: CANopen device specific.
    DeviceSpecific,
    /// A code outside every CiA 301 class (for example 11xxh or A000h); the
    /// raw value stays in the [`ErrorCode`].
    Unassigned,
}

impl ErrorClass {
    /// The class name as CiA 301 words it.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ErrorClass::NoError => "error reset or no error",
            ErrorClass::Generic => "generic error",
            ErrorClass::Current => "current",
            ErrorClass::Voltage => "voltage",
            ErrorClass::Temperature => "temperature",
            ErrorClass::DeviceHardware => "CANopen device hardware",
            ErrorClass::DeviceSoftware => "CANopen device software",
            ErrorClass::AdditionalModules => "additional modules",
            ErrorClass::Monitoring => "monitoring",
            ErrorClass::External => "external error",
            ErrorClass::AdditionalFunctions => "additional functions",
            ErrorClass::DeviceSpecific => "CANopen device specific",
            ErrorClass::Unassigned => "unassigned error code",
        }
    }
}

/// Which document names a code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Document {
    /// CiA 301 (application layer).
    Cia301,
    /// CiA 401 (generic I/O), shipped by CANopenNode.
    Cia401,
    /// CiA 418 (battery module).
    Cia418,
}

/// One named code or code range: `lo..=hi`, its name, and the document.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NamedCode {
    /// First code of the range.
    pub lo: u16,
    /// Last code of the range (equal to `lo` for a single code).
    pub hi: u16,
    /// The name, lower case as in running text.
    pub name: &'static str,
    /// Where the name comes from.
    pub document: Document,
}

const fn row(lo: u16, hi: u16, name: &'static str, document: Document) -> NamedCode {
    NamedCode {
        lo,
        hi,
        name,
        document,
    }
}

use Document::{Cia301, Cia401, Cia418};

/// Every named code and range, in the order of CiA 301's emergency error code table, then CiA 401's and CiA 418's.
/// [`ErrorCode::name`] picks the narrowest range containing a code.
#[rustfmt::skip]
pub const NAMED_CODES: &[NamedCode] = &[
    row(0x0000, 0x00FF, "error reset or no error", Cia301),
    row(0x1000, 0x10FF, "generic error", Cia301),
    row(0x2000, 0x20FF, "current", Cia301),
    row(0x2100, 0x21FF, "current, CANopen device input side", Cia301),
    row(0x2200, 0x22FF, "current inside the CANopen device", Cia301),
    row(0x2300, 0x23FF, "current, CANopen device output side", Cia301),
    row(0x3000, 0x30FF, "voltage", Cia301),
    row(0x3100, 0x31FF, "mains voltage", Cia301),
    row(0x3200, 0x32FF, "voltage inside the CANopen device", Cia301),
    row(0x3300, 0x33FF, "output voltage", Cia301),
    row(0x4000, 0x40FF, "temperature", Cia301),
    row(0x4100, 0x41FF, "ambient temperature", Cia301),
    row(0x4200, 0x42FF, "CANopen device temperature", Cia301),
    row(0x5000, 0x50FF, "CANopen device hardware", Cia301),
    row(0x6000, 0x60FF, "CANopen device software", Cia301),
    row(0x6100, 0x61FF, "internal software", Cia301),
    row(0x6200, 0x62FF, "user software", Cia301),
    row(0x6300, 0x63FF, "data set", Cia301),
    row(0x7000, 0x70FF, "additional modules", Cia301),
    row(0x8000, 0x80FF, "monitoring", Cia301),
    row(0x8100, 0x81FF, "communication", Cia301),
    row(0x8110, 0x8110, "CAN overrun (objects lost)", Cia301),
    row(0x8120, 0x8120, "CAN in error passive mode", Cia301),
    row(0x8130, 0x8130, "life guard error or heartbeat error", Cia301),
    row(0x8140, 0x8140, "recovered from bus off", Cia301),
    row(0x8150, 0x8150, "CAN-ID collision", Cia301),
    row(0x8200, 0x82FF, "protocol error", Cia301),
    row(0x8210, 0x8210, "PDO not processed due to length error", Cia301),
    row(0x8220, 0x8220, "PDO length exceeded", Cia301),
    row(0x8230, 0x8230, "DAM MPDO not processed, destination object not available", Cia301),
    row(0x8240, 0x8240, "unexpected SYNC data length", Cia301),
    row(0x8250, 0x8250, "RPDO timeout", Cia301),
    row(0x9000, 0x90FF, "external error", Cia301),
    row(0xF000, 0xF0FF, "additional functions", Cia301),
    row(0xFF00, 0xFFFF, "CANopen device specific", Cia301),
    row(0x2310, 0x2310, "current at outputs too high (overload)", Cia401),
    row(0x2320, 0x2320, "short circuit at outputs", Cia401),
    row(0x2330, 0x2330, "load dump at outputs", Cia401),
    row(0x3110, 0x3110, "input voltage too high", Cia401),
    row(0x3120, 0x3120, "input voltage too low", Cia401),
    row(0x3210, 0x3210, "internal voltage too high", Cia401),
    row(0x3220, 0x3220, "internal voltage too low", Cia401),
    row(0x3310, 0x3310, "output voltage too high", Cia401),
    row(0x3320, 0x3320, "output voltage too low", Cia401),
    row(0x5010, 0x5010, "temperature sensor fault", Cia418),
];

impl ErrorCode {
    /// The CiA 301 class of this code.
    #[must_use]
    pub const fn class(self) -> ErrorClass {
        let c = self.0;
        match c >> 8 {
            0x00 => ErrorClass::NoError,
            0x10 => ErrorClass::Generic,
            0x20..=0x2F => ErrorClass::Current,
            0x30..=0x3F => ErrorClass::Voltage,
            0x40..=0x4F => ErrorClass::Temperature,
            0x50 => ErrorClass::DeviceHardware,
            0x60..=0x6F => ErrorClass::DeviceSoftware,
            0x70 => ErrorClass::AdditionalModules,
            0x80..=0x8F => ErrorClass::Monitoring,
            0x90 => ErrorClass::External,
            0xF0 => ErrorClass::AdditionalFunctions,
            0xFF => ErrorClass::DeviceSpecific,
            _ => ErrorClass::Unassigned,
        }
    }

    /// The most specific name known for this code: an exact code if one is
    /// named, else the narrowest named range, else its class name.
    ///
    /// ```
    /// use canopen_codec::emcy::ErrorCode;
    /// assert_eq!(ErrorCode(0x8130).name(), "life guard error or heartbeat error");
    /// assert_eq!(ErrorCode(0x8131).name(), "communication");
    /// assert_eq!(ErrorCode(0x2ABC).name(), "current");
    /// assert_eq!(ErrorCode(0x5010).name(), "temperature sensor fault");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        self.named().map_or(self.class().name(), |n| n.name)
    }

    /// The narrowest [`NamedCode`] row containing this code, if any.
    #[must_use]
    pub fn named(self) -> Option<&'static NamedCode> {
        let c = self.0;
        NAMED_CODES
            .iter()
            .filter(|r| r.lo <= c && c <= r.hi)
            .min_by_key(|r| r.hi - r.lo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row of emcy_codes.tsv: both ends of the range name to the row
    /// (the narrowest one), and the class matches the first hex digit group.
    #[test]
    fn every_row_names_its_range() {
        for r in NAMED_CODES {
            for code in [r.lo, r.hi] {
                let narrowest = NAMED_CODES
                    .iter()
                    .filter(|o| o.lo <= code && code <= o.hi)
                    .all(|o| o.hi - o.lo >= r.hi - r.lo);
                if narrowest {
                    assert_eq!(ErrorCode(code).name(), r.name, "{code:04X}");
                }
            }
            assert_ne!(
                ErrorCode(r.lo).class(),
                ErrorClass::Unassigned,
                "{:04X}",
                r.lo
            );
        }
    }

    #[test]
    fn most_specific_wins() {
        assert_eq!(
            ErrorCode(0x8210).name(),
            "PDO not processed due to length error"
        );
        assert_eq!(ErrorCode(0x8200).name(), "protocol error");
        assert_eq!(ErrorCode(0x8000).name(), "monitoring");
        assert_eq!(
            ErrorCode(0x2310).name(),
            "current at outputs too high (overload)"
        );
        assert_eq!(
            ErrorCode(0x2311).name(),
            "current, CANopen device output side"
        );
        assert_eq!(ErrorCode(0x2400).name(), "current");
        assert_eq!(
            ErrorCode(0x5010).named().unwrap().document,
            Document::Cia418
        );
        assert_eq!(ErrorCode(0x5011).name(), "CANopen device hardware");
        assert_eq!(ErrorCode(0x8300).name(), "monitoring");
        assert_eq!(ErrorCode(0x0042).name(), "error reset or no error");
        assert_eq!(ErrorCode(0xA000).name(), "unassigned error code");
        assert_eq!(ErrorCode(0xA000).class(), ErrorClass::Unassigned);
        assert_eq!(ErrorCode(0x1100).class(), ErrorClass::Unassigned);
        assert_eq!(ErrorCode(0xFFFF).class(), ErrorClass::DeviceSpecific);
    }

    #[test]
    fn display() {
        assert_eq!(
            format!("{}", ErrorCode(0x8130)),
            "8130h life guard error or heartbeat error"
        );
    }
}
