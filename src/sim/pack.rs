//! A battery pack for simulation: series cells of a CiA 418 chemistry
//! (6020h sub 1's high nibble), a capacity, a rest-voltage curve per
//! chemistry, an internal resistance, and a lumped thermal mass that heats
//! with I²R and cools toward ambient. The state of charge integrates the
//! current the charger delivers.
//!
//! The curves are ours: per-cell rest voltages at 0, 10, ... 100 % state of
//! charge, typical of each chemistry at 25 degC. For the lead-acid and
//! nickel chemistries the last points include the rise of the charging
//! voltage near full (gassing), which is what makes a constant-voltage
//! stage taper: in absorption the current is (set point - rest voltage) /
//! resistance, and it falls as the rest voltage climbs toward the set
//! point. The model is simple on purpose: no hysteresis, no diffusion
//! time constants, coulombic efficiency 1.

use crate::cia418::{BatteryType, Chemistry};

/// Why a pack cannot be modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PackError {
    /// No curve for this chemistry (the model has lead acid, nickel
    /// cadmium, nickel metal hydride and lithium ion).
    #[error("no model for the chemistry {0:?} (lead acid, NiCd, NiMH and lithium ion have one)")]
    UnsupportedChemistry(Chemistry),
    /// Zero cells or zero capacity.
    #[error("a pack needs at least one cell and a capacity above zero")]
    Empty,
}

/// Per-cell rest voltage (V) at 0, 10, ... 100 % state of charge.
type Curve = [f64; 11];

const LEAD_ACID: Curve = [
    1.95, 1.98, 2.00, 2.02, 2.04, 2.06, 2.08, 2.10, 2.18, 2.32, 2.45,
];
const NICKEL_CADMIUM: Curve = [
    1.10, 1.20, 1.24, 1.26, 1.28, 1.30, 1.32, 1.34, 1.37, 1.42, 1.50,
];
const NICKEL_METAL_HYDRIDE: Curve = [
    1.10, 1.22, 1.25, 1.27, 1.29, 1.31, 1.33, 1.35, 1.38, 1.43, 1.50,
];
const LITHIUM_ION: Curve = [
    3.00, 3.45, 3.55, 3.62, 3.68, 3.75, 3.83, 3.92, 4.00, 4.08, 4.18,
];

/// The curve of `chemistry` and its cell resistance times capacity (Ohm
/// x Ah: a 100 Ah lead-acid cell has 6 mOhm; the figure lumps the
/// charging overvoltage into the resistance, so bulk ends near 85 %).
fn chemistry_model(chemistry: Chemistry) -> Option<(&'static Curve, f64)> {
    Some(match chemistry {
        Chemistry::LeadAcid => (&LEAD_ACID, 0.6),
        Chemistry::NickelCadmium => (&NICKEL_CADMIUM, 0.4),
        Chemistry::NickelMetalHydride => (&NICKEL_METAL_HYDRIDE, 0.4),
        Chemistry::LithiumIon => (&LITHIUM_ION, 0.2),
        _ => return None,
    })
}

/// What a pack is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PackSpec {
    /// The chemistry (CiA 418 6020h sub 1, high nibble).
    pub chemistry: Chemistry,
    /// The battery type (6020h sub 1, the whole byte: the chemistry and
    /// its variant, e.g. flooded or AGM lead acid).
    pub battery_type: BatteryType,
    /// Cells in series (6020h sub 4).
    pub cells: u16,
    /// Capacity, Ah (6020h sub 2).
    pub capacity_ah: f64,
    /// Internal resistance of the whole pack, Ohm.
    pub resistance_ohm: f64,
    /// Heat capacity, J/K.
    pub heat_capacity_j_per_k: f64,
    /// Thermal resistance to ambient, K/W.
    pub thermal_resistance_k_per_w: f64,
    /// Ambient temperature, degC.
    pub ambient_c: f64,
}

impl PackSpec {
    /// A pack of `cells` cells of `chemistry` and `capacity_ah`, with the
    /// chemistry's resistance and a thermal mass of 250 J/K per Ah
    /// (about 30 kg for 100 Ah of lead acid), 0.15 K/W to a 25 degC ambient.
    pub fn new(chemistry: Chemistry, cells: u16, capacity_ah: f64) -> Result<Self, PackError> {
        Self::of_type(
            BatteryType::from_u8(chemistry.code() << 4),
            cells,
            capacity_ah,
        )
    }

    /// The same for a whole 6020h battery type (`BatteryType::from_name("agm")`).
    pub fn of_type(
        battery_type: BatteryType,
        cells: u16,
        capacity_ah: f64,
    ) -> Result<Self, PackError> {
        let chemistry = battery_type.chemistry();
        let (_, r_ah) =
            chemistry_model(chemistry).ok_or(PackError::UnsupportedChemistry(chemistry))?;
        if cells == 0 || capacity_ah.is_nan() || capacity_ah <= 0.0 {
            return Err(PackError::Empty);
        }
        Ok(PackSpec {
            chemistry,
            battery_type,
            cells,
            capacity_ah,
            resistance_ohm: f64::from(cells) * r_ah / capacity_ah,
            heat_capacity_j_per_k: 250.0 * capacity_ah,
            thermal_resistance_k_per_w: 0.15,
            ambient_c: 25.0,
        })
    }

    /// The rest voltage of one cell at `soc` (0..=1), V.
    #[must_use]
    pub fn cell_rest_voltage(&self, soc: f64) -> f64 {
        let Some((curve, _)) = chemistry_model(self.chemistry) else {
            return 0.0;
        };
        let x = soc.clamp(0.0, 1.0) * 10.0;
        let i = (x as usize).min(9);
        let (a, b) = (
            curve.get(i).copied().unwrap_or(0.0),
            curve.get(i + 1).copied().unwrap_or(0.0),
        );
        a + (b - a) * (x - i as f64)
    }
}

/// A pack and its state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pack {
    spec: PackSpec,
    /// Cells shorted ([`Pack::short_cells`]), at most all of them.
    shorted: u16,
    soc: f64,
    temperature_c: f64,
    charged_ah: f64,
}

impl Pack {
    /// `spec` at state of charge `soc` (0..=1) and ambient temperature.
    #[must_use]
    pub fn new(spec: PackSpec, soc: f64) -> Self {
        Pack {
            spec,
            shorted: 0,
            soc: soc.clamp(0.0, 1.0),
            temperature_c: spec.ambient_c,
            charged_ah: 0.0,
        }
    }

    /// What it is.
    #[must_use]
    pub const fn spec(&self) -> &PackSpec {
        &self.spec
    }

    /// State of charge, 0..=1.
    #[must_use]
    pub const fn soc(&self) -> f64 {
        self.soc
    }

    /// Temperature, degC.
    #[must_use]
    pub const fn temperature_c(&self) -> f64 {
        self.temperature_c
    }

    /// The battery is held at `celsius` from now on (a bench's
    /// temperature: a pack in a climate chamber, or its sensor's reading in
    /// 6010h): its temperature and the ambient it cools toward both become
    /// `celsius`, so its own I²R heat rises above it again as it charges.
    pub fn set_temperature_c(&mut self, celsius: f64) {
        if celsius.is_finite() {
            self.temperature_c = celsius;
            self.spec.ambient_c = celsius;
        }
    }

    /// `n` more cells short-circuit (a failed cell whose separator gave
    /// way): each takes its share of the pack's rest voltage and
    /// resistance with it, so the pack's voltage drops by `n` cells'
    /// worth and a charger's per-cell thresholds, set for the whole count,
    /// are too high for what is left. At most every cell shorts.
    pub fn short_cells(&mut self, n: u16) {
        self.shorted = self.shorted.saturating_add(n).min(self.spec.cells);
    }

    /// Cells shorted so far.
    #[must_use]
    pub const fn shorted_cells(&self) -> u16 {
        self.shorted
    }

    /// Cells still working (in series, between the terminals).
    #[must_use]
    pub const fn working_cells(&self) -> u16 {
        self.spec.cells.saturating_sub(self.shorted)
    }

    /// The share of the pack between the terminals (1 with no cell
    /// shorted).
    fn working_share(&self) -> f64 {
        f64::from(self.working_cells()) / f64::from(self.spec.cells.max(1))
    }

    /// Ah charged since the pack was made.
    #[must_use]
    pub const fn charged_ah(&self) -> f64 {
        self.charged_ah
    }

    /// The pack's rest (open-circuit) voltage, V.
    #[must_use]
    pub fn rest_voltage(&self) -> f64 {
        f64::from(self.working_cells()) * self.spec.cell_rest_voltage(self.soc)
    }

    /// The resistance between the terminals (the working cells'), Ohm.
    fn resistance(&self) -> f64 {
        self.spec.resistance_ohm * self.working_share()
    }

    /// The terminal voltage while `current_a` flows in, V.
    #[must_use]
    pub fn terminal_voltage(&self, current_a: f64) -> f64 {
        self.rest_voltage() + current_a * self.resistance()
    }

    /// The current that holds the terminals at `volts` (0 when the pack is
    /// above it), A.
    #[must_use]
    pub fn current_at(&self, volts: f64) -> f64 {
        let r = self.resistance();
        if r <= 0.0 {
            // Every cell shorted: a dead short takes what the source gives.
            return if volts > 0.0 { f64::MAX } else { 0.0 };
        }
        ((volts - self.rest_voltage()) / r).max(0.0)
    }

    /// `current_a` flowed in for `seconds`: the charge and the heat.
    pub fn step(&mut self, seconds: f64, current_a: f64) {
        let ah = current_a * seconds / 3600.0;
        self.charged_ah += ah;
        self.soc = (self.soc + ah / self.spec.capacity_ah).clamp(0.0, 1.0);
        let heat_w = current_a * current_a * self.resistance();
        let loss_w =
            (self.temperature_c - self.spec.ambient_c) / self.spec.thermal_resistance_k_per_w;
        self.temperature_c += (heat_w - loss_w) * seconds / self.spec.heat_capacity_j_per_k;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lead_100() -> PackSpec {
        PackSpec::new(Chemistry::LeadAcid, 24, 100.0).unwrap()
    }

    #[test]
    fn rest_voltage_follows_the_curve() {
        let p = lead_100();
        assert!((p.cell_rest_voltage(0.0) - 1.95).abs() < 1e-9);
        assert!((p.cell_rest_voltage(0.55) - 2.07).abs() < 1e-9);
        assert!((p.cell_rest_voltage(0.85) - 2.25).abs() < 1e-9);
        assert!((p.cell_rest_voltage(1.0) - 2.45).abs() < 1e-9);
        assert!((p.cell_rest_voltage(7.0) - 2.45).abs() < 1e-9, "clamped");
        assert!((p.resistance_ohm - 0.144).abs() < 1e-12);
    }

    #[test]
    fn soc_integrates_the_current_and_heat_follows_i2r() {
        let mut pack = Pack::new(lead_100(), 0.2);
        for _ in 0..3600 {
            pack.step(1.0, 25.0);
        }
        assert!((pack.soc() - 0.45).abs() < 1e-9);
        assert!((pack.charged_ah() - 25.0).abs() < 1e-9);
        // 25 A x 25 A x 144 mOhm = 90 W into 25 kJ/K, losing to ambient.
        let t = pack.temperature_c();
        assert!(t > 30.0 && t < 25.0 + 90.0 * 0.15, "{t}");
        // It cools back toward ambient with no current.
        for _ in 0..60_000 {
            pack.step(1.0, 0.0);
        }
        assert!((pack.temperature_c() - 25.0).abs() < 0.1);
    }

    #[test]
    fn constant_voltage_current_tapers_to_zero_at_the_curve_top() {
        let mut pack = Pack::new(lead_100(), 0.9);
        let cv = 24.0 * 2.45;
        let first = pack.current_at(cv);
        for _ in 0..7200 {
            let i = pack.current_at(cv).min(25.0);
            pack.step(1.0, i);
        }
        assert!(first > 20.0, "{first}");
        assert!(pack.current_at(cv) < 1.0, "{}", pack.current_at(cv));
    }

    #[test]
    fn a_set_temperature_holds_and_shorted_cells_take_their_voltage() {
        let mut pack = Pack::new(lead_100(), 0.5);
        pack.set_temperature_c(-10.0);
        for _ in 0..3600 {
            pack.step(1.0, 0.0);
        }
        assert!((pack.temperature_c() + 10.0).abs() < 1e-9);
        pack.set_temperature_c(f64::NAN);
        assert!((pack.temperature_c() + 10.0).abs() < 1e-9);

        let whole = pack.rest_voltage();
        let at_58 = pack.current_at(58.0);
        pack.short_cells(2);
        assert_eq!((pack.shorted_cells(), pack.working_cells()), (2, 22));
        let per_cell = pack.spec().cell_rest_voltage(0.5);
        assert!((whole - pack.rest_voltage() - 2.0 * per_cell).abs() < 1e-9);
        // The same charging voltage over fewer cells drives more current.
        assert!(pack.current_at(58.0) > at_58);
        pack.short_cells(u16::MAX);
        assert_eq!(pack.working_cells(), 0);
        assert_eq!(pack.rest_voltage(), 0.0);
    }

    #[test]
    fn a_pack_of_a_named_type_keeps_its_byte() {
        let agm = BatteryType::from_name("agm").unwrap();
        let spec = PackSpec::of_type(agm, 24, 100.0).unwrap();
        assert_eq!(
            (spec.chemistry, spec.battery_type),
            (Chemistry::LeadAcid, agm)
        );
        assert_eq!(
            lead_100().battery_type,
            BatteryType::from_name("flooded").unwrap()
        );
    }

    #[test]
    fn unsupported_chemistries_and_empty_packs_are_errors() {
        assert_eq!(
            PackSpec::new(Chemistry::MetalAir, 10, 10.0),
            Err(PackError::UnsupportedChemistry(Chemistry::MetalAir))
        );
        assert_eq!(
            PackSpec::new(Chemistry::LeadAcid, 0, 10.0),
            Err(PackError::Empty)
        );
        assert_eq!(
            PackSpec::new(Chemistry::LeadAcid, 1, f64::NAN),
            Err(PackError::Empty)
        );
    }
}
