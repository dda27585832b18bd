//! The catalogue's data: every CiA 418 and Delta-Q object a PDO may carry,
//! with its name, width and interpretation.

use super::{CatalogueEntry, FlagsKind, Interpretation, Marker, Unit};

const fn scaled(
    index: u16,
    name: &'static str,
    bits: u8,
    frac_bits: u8,
    unit: Option<Unit>,
) -> CatalogueEntry {
    CatalogueEntry {
        index,
        first_sub: 0,
        last_sub: 0,
        name,
        bits,
        interpretation: Interpretation::Unsigned {
            frac_bits,
            unit,
            marker: Marker::None,
            max: None,
        },
    }
}

const fn other(index: u16, name: &'static str, bits: u8, i: Interpretation) -> CatalogueEntry {
    CatalogueEntry {
        index,
        first_sub: 0,
        last_sub: 0,
        name,
        bits,
        interpretation: i,
    }
}

impl CatalogueEntry {
    const fn subs(mut self, first: u8, last: u8) -> Self {
        self.first_sub = first;
        self.last_sub = last;
        self
    }

    const fn marked(mut self, marker: Marker, range_max: Option<u64>) -> Self {
        if let Interpretation::Unsigned {
            frac_bits, unit, ..
        } = self.interpretation
        {
            self.interpretation = Interpretation::Unsigned {
                frac_bits,
                unit,
                marker,
                max: range_max,
            };
        }
        self
    }
}

const A: Option<Unit> = Some(Unit::Ampere);
const V: Option<Unit> = Some(Unit::Volt);
const AH: Option<Unit> = Some(Unit::AmpereHour);
const PCT: Option<Unit> = Some(Unit::Percent);
const NO_16: Marker = Marker::NoValue(0xFFFF);

/// The CiA 418 application objects 6000h-6090h (DIGEST section 6).
pub const CIA418_OBJECTS: &[CatalogueEntry] = &[
    other(
        0x6000,
        "battery status",
        8,
        Interpretation::Flags(FlagsKind::BatteryStatus),
    ),
    other(
        0x6001,
        "charger status",
        8,
        Interpretation::Flags(FlagsKind::ChargerStatus),
    ),
    other(
        0x6010,
        "temperature",
        16,
        Interpretation::Signed {
            frac_bits: 3,
            unit: Some(Unit::DegreeCelsius),
        },
    ),
    scaled(0x6020, "battery parameters: highest sub-index", 8, 0, None),
    other(0x6020, "battery type", 8, Interpretation::BatteryType).subs(1, 1),
    scaled(0x6020, "Ah capacity", 16, 0, AH).subs(2, 2),
    scaled(0x6020, "maximum charge current", 16, 0, A).subs(3, 3),
    scaled(0x6020, "number of cells", 16, 0, None).subs(4, 4),
    scaled(0x6030, "battery serial number: elements", 8, 0, None),
    other(0x6030, "battery serial number", 32, Interpretation::Chars).subs(1, 3),
    scaled(0x6031, "battery ID: elements", 8, 0, None),
    other(0x6031, "battery ID", 32, Interpretation::Chars).subs(1, 5),
    scaled(0x6040, "vehicle serial number: elements", 8, 0, None),
    other(0x6040, "vehicle serial number", 32, Interpretation::Chars).subs(1, 5),
    scaled(0x6041, "vehicle ID: elements", 8, 0, None),
    other(0x6041, "vehicle ID", 32, Interpretation::Chars).subs(1, 5),
    scaled(0x6050, "cumulative total Ah charge", 32, 0, AH),
    scaled(0x6051, "Ah expended since last charge", 16, 3, AH),
    scaled(0x6052, "Ah returned during last charge", 16, 3, AH),
    scaled(0x6053, "Ah since last equalization", 16, 3, AH),
    scaled(0x6054, "date of last equalization: elements", 8, 0, None),
    scaled(
        0x6054,
        "last equalization, minutes since midnight",
        16,
        0,
        Some(Unit::Minute),
    )
    .subs(1, 1),
    scaled(
        0x6054,
        "last equalization, days since 1984-01-01",
        16,
        0,
        Some(Unit::Day),
    )
    .subs(2, 2),
    scaled(0x6060, "battery voltage", 32, 10, V),
    scaled(0x6070, "charge current requested", 16, 4, A).marked(Marker::Invalid(0xFFFF), None),
    scaled(0x6080, "charger state of charge", 8, 0, PCT).marked(Marker::Invalid(0xFF), Some(100)),
    scaled(0x6081, "battery state of charge", 8, 0, PCT).marked(Marker::Invalid(0xFF), Some(100)),
    other(
        0x6090,
        "water level status",
        8,
        Interpretation::Flags(FlagsKind::WaterLevelStatus),
    ),
];

/// The Delta-Q charger's objects (DIGEST sections 5 and 5a), including its
/// reading of 6052h. [`Catalogue::DeltaQCharger`](super::Catalogue::DeltaQCharger) looks here first, then in
/// [`CIA418_OBJECTS`].
pub const DELTAQ_OBJECTS: &[CatalogueEntry] = &[
    scaled(0x2002, "charging current", 16, 8, A).marked(NO_16, None),
    other(
        0x2006,
        "extended charge status",
        16,
        Interpretation::Flags(FlagsKind::ExtendedChargeStatus),
    ),
    other(
        0x2008,
        "derate reasons",
        8,
        Interpretation::Flags(FlagsKind::DerateReasons),
    ),
    other(
        0x2060,
        "displayed error",
        32,
        Interpretation::DisplayedError,
    ),
    scaled(0x2100, "battery voltage (legacy)", 16, 10, V).marked(NO_16, None),
    scaled(0x2101, "battery voltage", 16, 8, V).marked(NO_16, None),
    scaled(0x2200, "AC voltage", 16, 4, V).marked(NO_16, None),
    other(
        0x2241,
        "algorithm request",
        32,
        Interpretation::AlgorithmRequest,
    ),
    scaled(0x2271, "voltage request", 32, 10, V).marked(Marker::NoValue(0xFFFF_FFFF), None),
    scaled(0x2275, "cable resistance", 8, 0, Some(Unit::Milliohm)),
    scaled(0x2276, "voltage request", 16, 8, V).marked(NO_16, None),
    other(0x2FFA, "padding", 8, Interpretation::Padding).subs(1, 2),
    other(
        0x4201,
        "external override",
        8,
        Interpretation::Flags(FlagsKind::ExternalOverride),
    ),
    // The charger's 6052h: Q3 Ah like CiA 418, but 0xFFFF is "no value".
    scaled(0x6052, "Ah returned during last charge", 16, 3, AH).marked(NO_16, None),
];
