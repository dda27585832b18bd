//! Charge algorithms: the profile a local-mode charge cycle follows.
//!
//! Delta-Q's algorithm tables are its own and not published ("Delta-Q IC
//! Series CANopen interface specification rev 2.0", section 4.1 lists
//! "algorithm selection" and section 5 object 2241h selects one by id,
//! variant and flags). What an algorithm does here is **our** documented,
//! parametrised profile, the classic three-stage charge of industrial
//! chargers:
//!
//! 1. **Bulk** (constant current): `bulk_ma` until the output reaches
//!    `absorption_mv` (less [`ABSORPTION_ENTRY_PERMILLE`]).
//! 2. **Absorption** (constant voltage at `absorption_mv`): the pack's
//!    current tapers; the stage ends when it falls to `termination_ma` or
//!    after `absorption_max` (a safety timer).
//! 3. **Rest** (output off) for the charger's rest time, then **float**
//!    (constant voltage at `float_mv`, current limited to
//!    `float_ma`) when the algorithm has one, else **complete** (output off).
//!
//! Equalize (`equalize_mv` for `equalize_time`), where the algorithm has
//! it, runs after absorption when the BMS asks for it (4201h bit 0, local
//! override mode). An algorithm of kind [`AlgorithmKind::Float`] is the
//! "float algorithm" of the document's use case "complete charge via set
//! active algorithm to float" (section 7): selecting it ends the cycle and
//! floats the pack.
//!
//! Voltages and currents are whole-pack figures in millivolts and
//! milliamps; [`ChargeAlgorithm::lead_acid`] and
//! [`ChargeAlgorithm::lithium_ion`] derive them from a cell count and
//! the usual per-cell values.

use core::time::Duration;

/// The output must reach the absorption voltage less this many per mille
/// for bulk to end (the power stage regulates to the set point from below).
pub const ABSORPTION_ENTRY_PERMILLE: u32 = 5;

/// What selecting the algorithm does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AlgorithmKind {
    /// A whole charge cycle: bulk, absorption, rest, float or complete.
    Cycle,
    /// Float only: the cycle ends and the pack is held at `float_mv`.
    Float,
}

/// One charge algorithm (our profile; see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ChargeAlgorithm {
    /// Its id, as 2241h bits 0-15 select it.
    pub id: u16,
    /// A name for people.
    pub name: &'static str,
    /// Cycle or float only.
    pub kind: AlgorithmKind,
    /// Bulk (constant) current, mA.
    pub bulk_ma: u32,
    /// Absorption (constant) voltage, mV.
    pub absorption_mv: u32,
    /// Absorption ends when the current falls to this, mA.
    pub termination_ma: u32,
    /// Absorption ends at the latest after this long.
    pub absorption_max: Duration,
    /// Float voltage, mV (0: no float, the cycle ends complete).
    pub float_mv: u32,
    /// The current limit while floating, mA.
    pub float_ma: u32,
    /// Equalize voltage, mV (0: no equalize).
    pub equalize_mv: u32,
    /// How long equalize lasts.
    pub equalize_time: Duration,
    /// Above this output voltage the charger stops with E-0-0-1 "battery
    /// high voltage (threshold from the algorithm)", mV.
    pub high_voltage_mv: u32,
}

impl ChargeAlgorithm {
    /// A flooded lead-acid cycle for `cells` 2 V cells: absorption
    /// 2.45 V/cell, float 2.27 V/cell, equalize 2.58 V/cell for 2 h, high
    /// voltage at 2.65 V/cell; bulk at `bulk_ma`, termination at a
    /// twentieth of it, absorption at most 4 h. (Common flooded lead-acid
    /// figures at 25 degC; ours, not Delta-Q's.)
    #[must_use]
    pub const fn lead_acid(id: u16, name: &'static str, cells: u32, bulk_ma: u32) -> Self {
        ChargeAlgorithm {
            id,
            name,
            kind: AlgorithmKind::Cycle,
            bulk_ma,
            absorption_mv: cells * 2450,
            termination_ma: bulk_ma / 20,
            absorption_max: Duration::from_secs(4 * 3600),
            float_mv: cells * 2270,
            float_ma: bulk_ma / 10,
            equalize_mv: cells * 2580,
            equalize_time: Duration::from_secs(2 * 3600),
            high_voltage_mv: cells * 2650,
        }
    }

    /// A lithium-ion (NMC) cycle for `cells` cells in series: absorption
    /// 4.15 V/cell, termination at a twentieth of `bulk_ma`, absorption at
    /// most 2 h, no float and no equalize, high voltage at 4.25 V/cell.
    #[must_use]
    pub const fn lithium_ion(id: u16, name: &'static str, cells: u32, bulk_ma: u32) -> Self {
        ChargeAlgorithm {
            id,
            name,
            kind: AlgorithmKind::Cycle,
            bulk_ma,
            absorption_mv: cells * 4150,
            termination_ma: bulk_ma / 20,
            absorption_max: Duration::from_secs(2 * 3600),
            float_mv: 0,
            float_ma: 0,
            equalize_mv: 0,
            equalize_time: Duration::ZERO,
            high_voltage_mv: cells * 4250,
        }
    }

    /// The float-only algorithm of `cycle`: selecting it floats the pack
    /// at `cycle`'s float voltage and float current (or, without a float,
    /// its absorption voltage and termination current).
    #[must_use]
    pub const fn float_of(id: u16, name: &'static str, cycle: &ChargeAlgorithm) -> Self {
        let float_mv = if cycle.float_mv == 0 {
            cycle.absorption_mv
        } else {
            cycle.float_mv
        };
        let float_ma = if cycle.float_ma == 0 {
            cycle.termination_ma
        } else {
            cycle.float_ma
        };
        ChargeAlgorithm {
            id,
            name,
            kind: AlgorithmKind::Float,
            float_mv,
            float_ma,
            ..*cycle
        }
    }
}

/// Our example table for a 48 V system (the ICL1500's class: 1.5 kW, up to
/// 25 A at 48 V): ids 1-2 lead acid (24 cells, 25 A and 12 A), 11 and 13
/// lithium ion (13 cells, 25 A and 12 A; the document's 2241h example value
/// 0x8000000B selects algorithm 11), 3 and 12 the float algorithms of 1
/// and 11. Applications bring their own
/// table ([`ChargeConfig::algorithms`](super::ChargeConfig::algorithms)).
pub const EXAMPLE_ALGORITHMS: [ChargeAlgorithm; 6] = [
    ChargeAlgorithm::lead_acid(1, "flooded lead acid 48 V, 25 A", 24, 25_000),
    ChargeAlgorithm::lead_acid(2, "flooded lead acid 48 V, 12 A", 24, 12_000),
    ChargeAlgorithm::float_of(
        3,
        "float, flooded lead acid 48 V",
        &ChargeAlgorithm::lead_acid(1, "", 24, 25_000),
    ),
    ChargeAlgorithm::lithium_ion(11, "lithium ion 13s (48 V), 25 A", 13, 25_000),
    ChargeAlgorithm::lithium_ion(13, "lithium ion 13s (48 V), 12 A", 13, 12_000),
    ChargeAlgorithm::float_of(
        12,
        "float, lithium ion 13s",
        &ChargeAlgorithm::lithium_ion(11, "", 13, 25_000),
    ),
];

/// The algorithm `id` of `table`.
#[must_use]
pub fn find(table: &[ChargeAlgorithm], id: u16) -> Option<&ChargeAlgorithm> {
    table.iter().find(|a| a.id == id)
}
