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
//! milliamps; [`ChargeAlgorithm::for_cells`] derives them from a cell
//! count and a chemistry's per-cell figures ([`CellFigures`]: [`FLOODED`],
//! [`AGM`], [`GEL`], [`NICKEL_CADMIUM`], [`NICKEL_METAL_HYDRIDE`],
//! [`LITHIUM_ION`]), each for a CiA 418 battery type (6020h sub 1).
//!
//! ## Chemistry, temperature and state of charge
//!
//! - [`select`] picks a table's algorithm for the battery the module
//!   reports in 6020h (its type and cell count): a nickel pack never gets
//!   the lead-acid curve. Nothing matching: `None` (the charger keeps its
//!   configured algorithm, or its no-CAN default without a module).
//! - [`ChargeAlgorithm::compensated`] moves the voltages with the
//!   battery's temperature (6010h): lead acid -4 mV/cell/degC and nickel
//!   -3 mV/cell/degC around 25 degC, because the gassing voltage falls as
//!   the battery warms ("Handbook of Batteries", Linden and Reddy, 3rd
//!   ed., chapter 23; Saft's nickel-cadmium technical manual); lithium
//!   ion none.
//! - [`ChargeAlgorithm::estimate_soc`] is the charger's own state of
//!   charge (6080h): the start from the battery's rest voltage when the
//!   cycle began, plus the Ah delivered times the chemistry's charge
//!   efficiency over the capacity.

use core::time::Duration;

/// The output must reach the absorption voltage less this many per mille
/// for bulk to end (the power stage regulates to the set point from below).
pub const ABSORPTION_ENTRY_PERMILLE: u32 = 5;

/// One chemistry's charge, per cell at 25 degC (ours: common figures for
/// each chemistry, sources on each constant).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CellFigures {
    /// The battery type the figures are for (6020h sub 1, CiA 418
    /// appendix A).
    pub battery_type: u8,
    /// Absorption (constant-voltage) voltage, mV.
    pub absorption_mv: u32,
    /// Float voltage, mV (0: no float).
    pub float_mv: u32,
    /// Equalize voltage, mV (0: no equalize).
    pub equalize_mv: u32,
    /// E-0-0-1 "battery high voltage" above this, mV.
    pub high_mv: u32,
    /// Temperature compensation of the voltages, uV per degC above 25
    /// degC (negative: lower when warm; 0: none).
    pub compensation_uv: i32,
    /// Rest voltage of an empty cell, mV (the start of the charger's
    /// state-of-charge estimate).
    pub rest_empty_mv: u32,
    /// Rest voltage of a full cell, mV.
    pub rest_full_mv: u32,
    /// The share of the Ah delivered the battery stores, per mille (the
    /// charger's estimate).
    pub efficiency_permille: u32,
    /// Absorption lasts at most this long.
    pub absorption_max: Duration,
}

/// The chemistries' [`CellFigures`], one row each, the columns in the
/// struct's order: the battery type (6020h sub 1); the absorption, float,
/// equalize and high voltages, mV per cell (0: no float, no equalize); the
/// temperature compensation, uV per cell per degC; the rest voltages of an
/// empty and a full cell, mV; the efficiency, per mille; the longest
/// absorption, hours.
macro_rules! cell_figures {
    ($(
        $(#[$doc:meta])*
        $name:ident: $type:literal | $absorption:literal $float:literal $equalize:literal
        $high:literal | $compensation:literal | $empty:literal $full:literal | $efficiency:literal
        | $hours:literal h;
    )*) => {$(
        $(#[$doc])*
        pub const $name: CellFigures = CellFigures {
            battery_type: $type,
            absorption_mv: $absorption,
            float_mv: $float,
            equalize_mv: $equalize,
            high_mv: $high,
            compensation_uv: $compensation,
            rest_empty_mv: $empty,
            rest_full_mv: $full,
            efficiency_permille: $efficiency,
            absorption_max: Duration::from_secs($hours * 3600),
        };
    )*};
}

cell_figures! {
    //                       type | absorb float equal high | uV/degC | rest empty full | per mille | absorb max
    /// Flooded lead acid (0001 0000): absorption 2.45, float 2.27,
    /// equalize 2.58, high 2.65 V/cell, -4 mV/cell/degC ("Battery
    /// University" BU-403 "Charging lead acid": 2.40-2.45 V absorption,
    /// 2.25-2.27 float, 3-5 mV per degC); rest 1.94-2.12 V/cell (OCV =
    /// specific gravity + 0.84 V, "Handbook of Batteries" ch. 23); 90 %
    /// efficiency (a flooded battery takes 105-130 % of its discharge back);
    /// absorption at most 4 h.
    FLOODED:                 0x10 | 2450   2270  2580  2650 |   -4000 | 1940 2120       |       900 | 4 h;
    /// AGM lead acid (0001 1000): absorption 2.40, float 2.27, no equalize
    /// (it would vent and dry a valve-regulated cell), high 2.50 V/cell,
    /// -4 mV/cell/degC; rest 1.97-2.15 V/cell; 95 % efficiency (oxygen
    /// recombination) (BU-403; manufacturers' AGM charging guides).
    AGM:                     0x18 | 2400   2270     0  2500 |   -4000 | 1970 2150       |       950 | 4 h;
    /// Gel lead acid (0001 1001): as AGM with a lower absorption voltage,
    /// 2.35 V/cell, float 2.25 V/cell (gel cells gas and void at AGM
    /// voltages; BU-403).
    GEL:                     0x19 | 2350   2250     0  2450 |   -4000 | 1970 2150       |       950 | 4 h;
    /// Nickel cadmium (0010 0000, vented pocket plates): charge 1.50, float
    /// 1.40, high 1.65 V/cell, -3 mV/cell/degC; rest 1.10-1.32 V/cell; 80 %
    /// efficiency (charge factor 1.2-1.4); absorption at most 6 h (Saft,
    /// "Nickel-cadmium batteries for stationary applications, technical
    /// manual": float 1.40-1.42, charge 1.50-1.65 V/cell).
    NICKEL_CADMIUM:          0x20 | 1500   1400     0  1650 |   -3000 | 1100 1320       |       800 | 6 h;
    /// Nickel metal hydride (1000 0000): charge 1.48, high 1.60 V/cell, no
    /// float (a NiMH cell kept on float overheats; a finished charge ends
    /// complete), -3 mV/cell/degC; rest 1.15-1.38 V/cell; 85 % efficiency
    /// ("Handbook of Batteries" ch. 30: charge input 120-150 %).
    NICKEL_METAL_HYDRIDE:    0x80 | 1480      0     0  1600 |   -3000 | 1150 1380       |       850 | 4 h;
    /// Lithium ion (1010 0000, NMC): absorption 4.15, high 4.25 V/cell, no
    /// float, no equalize, no temperature compensation (a lithium cell has
    /// no gassing to compensate; its limit is a fixed voltage); rest
    /// 3.00-4.18 V/cell; 99 % efficiency; absorption at most 2 h ("Battery
    /// University" BU-409 "Charging lithium-ion").
    LITHIUM_ION:             0xA0 | 4150      0     0  4250 |       0 | 3000 4180       |       990 | 2 h;
}

/// The figures for a battery type byte (6020h sub 1): the lead-acid
/// kinds by their bits (maintenance free: AGM, gel, hybrid as AGM;
/// flooded otherwise), nickel cadmium, nickel metal hydride, lithium
/// ion; `None` for the chemistries we have no figures for.
#[must_use]
pub const fn figures_for(battery_type: u8) -> Option<&'static CellFigures> {
    match battery_type >> 4 {
        0b0001 if battery_type & 0x0B == 0x09 => Some(&GEL),
        0b0001 if battery_type & 0x08 != 0 => Some(&AGM),
        0b0001 => Some(&FLOODED),
        0b0010 => Some(&NICKEL_CADMIUM),
        0b1000 => Some(&NICKEL_METAL_HYDRIDE),
        0b1010 => Some(&LITHIUM_ION),
        _ => None,
    }
}

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
    /// Cells in series it charges (6020h sub 4).
    pub cells: u32,
    /// Its chemistry's per-cell figures (the battery type it is for,
    /// temperature compensation, the state-of-charge estimate).
    pub cell: &'static CellFigures,
}

impl ChargeAlgorithm {
    /// A cycle for `cells` cells of `cell`'s chemistry at `bulk_ma`: its
    /// absorption, float, equalize and high voltages times the cells,
    /// termination at a twentieth of the bulk current, float current at
    /// most a tenth, equalize for 2 h.
    #[must_use]
    pub const fn for_cells(
        id: u16,
        name: &'static str,
        cell: &'static CellFigures,
        cells: u32,
        bulk_ma: u32,
    ) -> Self {
        ChargeAlgorithm {
            id,
            name,
            kind: AlgorithmKind::Cycle,
            bulk_ma,
            absorption_mv: cells * cell.absorption_mv,
            termination_ma: bulk_ma / 20,
            absorption_max: cell.absorption_max,
            float_mv: cells * cell.float_mv,
            float_ma: if cell.float_mv == 0 { 0 } else { bulk_ma / 10 },
            equalize_mv: cells * cell.equalize_mv,
            equalize_time: if cell.equalize_mv == 0 {
                Duration::ZERO
            } else {
                Duration::from_secs(2 * 3600)
            },
            high_voltage_mv: cells * cell.high_mv,
            cells,
            cell,
        }
    }

    /// A flooded lead-acid cycle for `cells` 2 V cells ([`FLOODED`]):
    /// absorption 2.45 V/cell, float 2.27 V/cell, equalize 2.58 V/cell for
    /// 2 h, high voltage at 2.65 V/cell; bulk at `bulk_ma`, termination at
    /// a twentieth of it, absorption at most 4 h.
    #[must_use]
    pub const fn lead_acid(id: u16, name: &'static str, cells: u32, bulk_ma: u32) -> Self {
        Self::for_cells(id, name, &FLOODED, cells, bulk_ma)
    }

    /// A lithium-ion (NMC) cycle for `cells` cells in series
    /// ([`LITHIUM_ION`]): absorption 4.15 V/cell, termination at a
    /// twentieth of `bulk_ma`, absorption at most 2 h, no float and no
    /// equalize, high voltage at 4.25 V/cell.
    #[must_use]
    pub const fn lithium_ion(id: u16, name: &'static str, cells: u32, bulk_ma: u32) -> Self {
        Self::for_cells(id, name, &LITHIUM_ION, cells, bulk_ma)
    }

    /// `mv` (one of the algorithm's voltages) compensated for the
    /// battery at `battery_c` (6010h, whole degC; `None`: no sensor, no
    /// compensation): [`CellFigures::compensation_uv`] per cell per degC
    /// from 25 degC, the temperature taken within -20..=50 degC (beyond
    /// that the charge pauses with E-0-0-8 anyway, and a broken sensor's
    /// reading must not swing the voltage without bound).
    #[must_use]
    pub fn compensated(&self, mv: u32, battery_c: Option<i16>) -> u32 {
        let Some(t) = battery_c else { return mv };
        if mv == 0 {
            return 0;
        }
        // In 32 bits (a 64-bit division is a library routine on the
        // charger's controller), saturating.
        let delta_c = i32::from(t.clamp(-20, 50)) - 25;
        let cells = i32::try_from(self.cells).unwrap_or(i32::MAX);
        let uv = self
            .cell
            .compensation_uv
            .saturating_mul(delta_c)
            .saturating_mul(cells);
        let d = uv / 1000;
        if d >= 0 {
            mv.saturating_add(d.unsigned_abs())
        } else {
            mv.saturating_sub(d.unsigned_abs())
        }
    }

    /// The charger's state of charge estimate (6080h, percent): the
    /// battery's rest voltage `start_mv` when the cycle began (between
    /// the chemistry's empty and full rest voltages) plus the charge
    /// delivered since, `delivered_q3` (Q3 Ah, as 6052h), times the
    /// chemistry's efficiency over `capacity_ah` (6020h sub 2; 0: the bulk
    /// current taken as C/4, our tables' rate). At most 99: only the end
    /// of the cycle says full.
    #[must_use]
    pub fn estimate_soc(&self, start_mv: u32, delivered_q3: u32, capacity_ah: u32) -> u8 {
        // In 32 bits (a 64-bit division is a library routine on the
        // charger's controller): the span is at most 2^16 mV x 2^16 cells
        // only in theory, so both factors are bounded first.
        let c = self.cell;
        let cells = self.cells.min(1000);
        let empty = c.rest_empty_mv.min(65_535) * cells;
        let span = (c.rest_full_mv.min(65_535).saturating_sub(c.rest_empty_mv) * cells).max(1);
        let below = start_mv.saturating_sub(empty).min(span);
        // Per mille of the span, without overflow: span < 2^26.
        let start = below / span * 1000 + below % span * 1000 / span;
        let capacity = if capacity_ah == 0 {
            (self.bulk_ma / 250).max(1)
        } else {
            capacity_ah.min(65_535)
        };
        // Q3 Ah x per mille / (8 x Ah) = per mille of the capacity; the
        // charge counted at most twice the capacity (it says 99 % then).
        let delivered = delivered_q3.min(16 * capacity);
        let added = delivered * c.efficiency_permille.min(1000) / (8 * capacity);
        ((start + added) / 10).min(99) as u8
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
/// 25 A at 48 V): ids 1-2 flooded lead acid (24 cells, 25 A and 12 A), 4
/// AGM and 5 gel (24 cells, 25 A), 11 and 13 lithium ion (13 cells, 25 A
/// and 12 A; the document's 2241h example value 0x8000000B selects
/// algorithm 11), 21 nickel cadmium and 31 nickel metal hydride (40
/// cells, 25 A), 3, 12 and 22 the float algorithms of 1, 11 and 21.
/// Applications bring their own table
/// ([`ChargeConfig::algorithms`](super::ChargeConfig::algorithms)).
pub const EXAMPLE_ALGORITHMS: [ChargeAlgorithm; 10] = [
    ChargeAlgorithm::lead_acid(1, "flooded lead acid 48 V, 25 A", 24, 25_000),
    ChargeAlgorithm::lead_acid(2, "flooded lead acid 48 V, 12 A", 24, 12_000),
    ChargeAlgorithm::float_of(
        3,
        "float, flooded lead acid 48 V",
        &ChargeAlgorithm::lead_acid(1, "", 24, 25_000),
    ),
    ChargeAlgorithm::for_cells(4, "AGM lead acid 48 V, 25 A", &AGM, 24, 25_000),
    ChargeAlgorithm::for_cells(5, "gel lead acid 48 V, 25 A", &GEL, 24, 25_000),
    ChargeAlgorithm::lithium_ion(11, "lithium ion 13s (48 V), 25 A", 13, 25_000),
    ChargeAlgorithm::lithium_ion(13, "lithium ion 13s (48 V), 12 A", 13, 12_000),
    ChargeAlgorithm::float_of(
        12,
        "float, lithium ion 13s",
        &ChargeAlgorithm::lithium_ion(11, "", 13, 25_000),
    ),
    ChargeAlgorithm::for_cells(
        21,
        "NiCd 40 cells (48 V), 25 A",
        &NICKEL_CADMIUM,
        40,
        25_000,
    ),
    ChargeAlgorithm::for_cells(
        31,
        "NiMH 40 cells (48 V), 25 A",
        &NICKEL_METAL_HYDRIDE,
        40,
        25_000,
    ),
];

/// The algorithm of `table` for the battery a module reports in 6020h:
/// its type (sub 1) and cells (sub 4). The first cycle algorithm for
/// exactly that type and cell count, else the first for the same
/// chemistry's figures ([`figures_for`]: a hybrid lead-acid battery takes
/// an AGM algorithm) and cell count, else `None` (no algorithm of the
/// table fits: the charger keeps its own).
///
/// ```
/// use canopen_codec::deltaq::charge::algorithm::{select, EXAMPLE_ALGORITHMS};
/// // NiCd, 40 cells: the NiCd algorithm, not the lead-acid one.
/// assert_eq!(select(&EXAMPLE_ALGORITHMS, 0x20, 40).map(|a| a.id), Some(21));
/// assert_eq!(select(&EXAMPLE_ALGORITHMS, 0xA0, 13).map(|a| a.id), Some(11));
/// assert_eq!(select(&EXAMPLE_ALGORITHMS, 0x20, 24), None);
/// ```
#[must_use]
pub fn select(table: &[ChargeAlgorithm], battery_type: u8, cells: u16) -> Option<&ChargeAlgorithm> {
    let cycles = || {
        table
            .iter()
            .filter(move |a| a.kind == AlgorithmKind::Cycle && a.cells == u32::from(cells))
    };
    cycles()
        .find(|a| a.cell.battery_type == battery_type)
        .or_else(|| {
            let figures = figures_for(battery_type)?;
            cycles().find(|a| a.cell == figures)
        })
}

/// The algorithm `id` of `table`.
#[must_use]
pub fn find(table: &[ChargeAlgorithm], id: u16) -> Option<&ChargeAlgorithm> {
    table.iter().find(|a| a.id == id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn select_takes_the_type_then_the_chemistry_and_the_cells() {
        let pick = |t: u8, cells: u16| select(&EXAMPLE_ALGORITHMS, t, cells).map(|a| a.id);
        assert_eq!(pick(0x10, 24), Some(1));
        // Tubular flooded: flooded figures; hybrid: AGM's; gel its own.
        assert_eq!(pick(0x11, 24), Some(1));
        assert_eq!(pick(0x18, 24), Some(4));
        assert_eq!(pick(0x1A, 24), Some(4));
        assert_eq!(pick(0x19, 24), Some(5));
        assert_eq!(pick(0x20, 40), Some(21));
        assert_eq!(pick(0x28, 40), Some(21), "sealed NiCd");
        assert_eq!(pick(0x80, 40), Some(31));
        assert_eq!(pick(0xA0, 13), Some(11));
        // No fit: another cell count, a chemistry without figures.
        assert_eq!(pick(0x10, 12), None);
        assert_eq!(pick(0x40, 24), None);
        assert_eq!(pick(0xC0, 24), None);
        // A float algorithm is never what a battery selects.
        let floats = [EXAMPLE_ALGORITHMS[2]];
        assert_eq!(select(&floats, 0x10, 24), None);
    }

    #[test]
    fn figures_follow_the_appendix_a_bits() {
        assert_eq!(figures_for(0x10), Some(&FLOODED));
        assert_eq!(figures_for(0x13), Some(&FLOODED));
        assert_eq!(figures_for(0x1C), Some(&AGM), "reserved bit x ignored");
        assert_eq!(figures_for(0x1D), Some(&GEL));
        assert_eq!(figures_for(0x21), Some(&NICKEL_CADMIUM));
        assert_eq!(figures_for(0x8F), Some(&NICKEL_METAL_HYDRIDE));
        assert_eq!(figures_for(0xA5), Some(&LITHIUM_ION));
        assert_eq!(figures_for(0x00), None);
        assert_eq!(figures_for(0x50), None);
        // Each table's algorithm carries its chemistry's voltages.
        let nicd = EXAMPLE_ALGORITHMS.iter().find(|a| a.id == 21).unwrap();
        assert_eq!((nicd.absorption_mv, nicd.float_mv), (60_000, 56_000));
        let nimh = EXAMPLE_ALGORITHMS.iter().find(|a| a.id == 31).unwrap();
        assert_eq!((nimh.float_mv, nimh.float_ma, nimh.equalize_mv), (0, 0, 0));
        assert_eq!(nimh.high_voltage_mv, 64_000);
    }

    #[test]
    fn lead_acid_voltages_fall_as_the_battery_warms() {
        let a = ChargeAlgorithm::lead_acid(1, "", 24, 25_000);
        assert_eq!(a.compensated(58_800, Some(25)), 58_800);
        // -4 mV/cell/degC: 10 degC warmer is 0.96 V lower for 24 cells.
        assert_eq!(a.compensated(58_800, Some(35)), 57_840);
        assert_eq!(a.compensated(58_800, Some(0)), 61_200);
        // Taken within -20..=50 degC; no sensor, no compensation.
        assert_eq!(a.compensated(58_800, Some(-40)), 63_120);
        assert_eq!(a.compensated(58_800, Some(i16::MAX)), 56_400);
        assert_eq!(a.compensated(58_800, None), 58_800);
        // Nothing to compensate, or a chemistry without compensation.
        assert_eq!(a.compensated(0, Some(0)), 0);
        let li = ChargeAlgorithm::lithium_ion(11, "", 13, 25_000);
        assert_eq!(li.compensated(53_950, Some(40)), 53_950);
    }

    #[test]
    fn the_charge_control_compensates_for_the_modules_temperature() {
        use super::super::tests::{bms, control, pack, s};
        use super::super::{BusInputs, ChargePhase};
        use crate::deltaq::OperatingMode;
        // Local mode, flooded lead acid 24 cells: bulk's voltage limit is
        // 58.80 V at 25 degC, 0.96 V lower at 35 degC, 2.40 V higher at
        // 0 degC (6010h in 1/8 degC).
        for (celsius, mv) in [(25, 58_800), (35, 57_840), (0, 61_200)] {
            let mut c = control(OperatingMode::Local);
            let at = BusInputs {
                battery_temperature: celsius * 8,
                ..bms(0)
            };
            c.handle_bus(s(0), at);
            c.handle_power_stage(s(0), pack(50, 0));
            assert_eq!(c.phase(), ChargePhase::Bulk);
            assert_eq!(c.set_points().voltage_mv, mv, "{celsius} degC");
            // Bulk ends at the compensated voltage (less 5 per mille):
            // 57.60 V ends it at 35 degC only.
            let at_57_6 = super::super::PowerStage {
                voltage_mv: 57_600,
                ..pack(0, 25)
            };
            c.handle_power_stage(s(1), at_57_6);
            let ends = c.phase() == ChargePhase::Absorption;
            assert_eq!(ends, celsius == 35, "{celsius} degC");
        }
    }

    #[test]
    fn the_state_of_charge_estimate_counts_from_the_start_voltage() {
        let a = ChargeAlgorithm::lead_acid(1, "", 24, 25_000);
        // 2.03 V/cell at rest: half way from 1.94 to 2.12.
        assert_eq!(a.estimate_soc(24 * 2030, 0, 100), 50);
        // 40 Ah delivered at 90 %: 36 % more.
        assert_eq!(a.estimate_soc(24 * 2030, 40 * 8, 100), 86);
        // Never full before the cycle says so; nothing below empty.
        assert_eq!(a.estimate_soc(24 * 2030, 200 * 8, 100), 99);
        assert_eq!(a.estimate_soc(0, 0, 100), 0);
        assert_eq!(a.estimate_soc(u32::MAX, 0, 100), 99);
        // No capacity: the bulk current as C/4, 100 Ah.
        assert_eq!(a.estimate_soc(24 * 1940, 40 * 8, 0), 36);
        assert_eq!(a.estimate_soc(24 * 1940, u32::MAX, 1), 99);
    }
}
