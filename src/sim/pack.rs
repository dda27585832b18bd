//! A battery pack for simulation: series cells of a CiA 418 battery type
//! (6020h sub 1), a capacity, and per chemistry a rest (open-circuit)
//! voltage curve, the charge reaction's resistance and acceptance, a side
//! reaction (gassing) and a charge efficiency; a lumped thermal mass heats
//! with every watt not stored and cools toward ambient.
//!
//! ## The model ([`CellModel`], per cell, scaled by the capacity)
//!
//! A charging current splits between two reactions in parallel:
//!
//! - the **charge reaction**, `(v - ocv(soc)) / (r + k soc / (1 - soc))`
//!   times the capacity: `r` is the ohmic and polarisation resistance,
//!   `k soc / (1 - soc)` the falling charge acceptance near full, which
//!   is what makes a constant-voltage stage taper (its current reaches 0 at
//!   full). Of its charge the share `efficiency` is stored; the rest is
//!   lost to heat (the coulombic efficiency of the charge reaction).
//! - the **side reaction** (water electrolysis in lead acid, oxygen
//!   evolution in nickel cells), `gas_c` times the capacity at `gas_v`,
//!   growing e-fold every `gas_slope_v` (a Tafel line), and setting in
//!   `gas_temp_v` per kelvin earlier above 25 degC. It stores nothing. It
//!   is the float current of a full pack, and why a lead-acid charger
//!   lowers its voltages when the battery is warm (temperature
//!   compensation).
//!
//! So a flooded lead-acid pack takes 105-130 % of the Ah it lacks, a
//! nickel pack 120-140 %, lithium ion a hair over 100 %; a full pack on
//! float draws a small current that all goes into gas and heat. At rest (no
//! current) the terminal voltage is the rest curve: lead acid about
//! 2.12 V/cell full (not the 2.4 V of the end of a charge).
//!
//! Sources of the figures (each constant says which): the rest voltages
//! and charge voltages of lead acid from "Handbook of Batteries" (Linden
//! and Reddy, 3rd ed., chapter 23 "Lead-acid batteries", the open-circuit
//! voltage from the electrolyte's specific gravity, OCV = SG + 0.84 V) and
//! "Battery University" BU-403 "Charging lead acid" (absorption 2.40-2.45,
//! float 2.25-2.27 V/cell, -3 mV/cell/degC); nickel cadmium from Saft's
//! "Nickel-cadmium batteries for stationary applications, technical
//! manual" (float 1.40-1.42 V/cell, charge 1.50-1.65 V/cell, charge
//! factor 1.2-1.4); nickel metal hydride from "Handbook of Batteries"
//! chapter 30 (charge input 120-150 %); lithium ion (NMC) from BU-409
//! "Charging lithium-ion" (4.20 V/cell limit, no charge below 0 degC:
//! lithium plating). The rest is ours, chosen so that a 0.25 C bulk
//! reaches the absorption voltage near 80 % (lead acid) or 85 % (nickel).

use crate::cia418::{BatteryType, Chemistry, LeadAcid};

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

/// One chemistry's cell, per Ah of capacity at 25 degC (see the module
/// docs for the equations).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellModel {
    /// Rest (open-circuit) voltage at 0, 10, ... 100 %, V.
    pub ocv: Curve,
    /// Ohmic and polarisation resistance times capacity, Ohm Ah.
    pub r_ah: f64,
    /// Charge acceptance `k`: the charge reaction's resistance grows by
    /// `k soc / (1 - soc)` Ohm Ah.
    pub acceptance_ah: f64,
    /// The side reaction draws `gas_c` C at `gas_v` (25 degC).
    pub gas_c: f64,
    /// Cell voltage where the side reaction draws `gas_c` C, V.
    pub gas_v: f64,
    /// The side current grows e-fold every this many volts.
    pub gas_slope_v: f64,
    /// The side reaction sets in this many volts later per kelvin above
    /// 25 degC (negative: earlier when warm).
    pub gas_temp_v: f64,
    /// The share of the charge reaction's charge that is stored.
    pub efficiency: f64,
    /// The most a cell may see, V (the manufacturers' limit; a test bench
    /// checks a charge never passes it).
    pub max_v: f64,
    /// The nominal cell voltage, V (2.0 lead acid, 1.2 nickel, 3.7
    /// lithium ion).
    pub nominal_v: f64,
    /// Heat capacity per Wh of nominal energy, J/K: the pack's mass per Wh
    /// (lead acid and nickel about 35 Wh/kg, lithium ion 120 Wh/kg at pack
    /// level) times about 0.9 kJ/(kg K).
    pub heat_j_per_k_wh: f64,
}

/// The chemistries' [`CellModel`]s, one row each: the rest voltage curve
/// (V at 0, 10, ... 100 %), then the other columns in the struct's order:
/// resistance and charge acceptance (Ohm Ah), the side reaction's current
/// (C) at its voltage (V), its slope (V per e-fold) and its temperature
/// shift (V/K), the charge efficiency, the highest and the nominal cell
/// voltage (V) and the heat capacity (J/K per Wh).
macro_rules! cell_models {
    ($(
        $(#[$doc:meta])*
        $name:ident: [$($ocv:literal)*]
        $r:literal $acceptance:literal | $gas_c:literal $gas_v:literal $slope:literal $temp:literal
        | $efficiency:literal | $max:literal $nominal:literal | $heat:literal;
    )*) => {$(
        $(#[$doc])*
        pub const $name: CellModel = CellModel {
            ocv: [$($ocv),*],
            r_ah: $r,
            acceptance_ah: $acceptance,
            gas_c: $gas_c,
            gas_v: $gas_v,
            gas_slope_v: $slope,
            gas_temp_v: $temp,
            efficiency: $efficiency,
            max_v: $max,
            nominal_v: $nominal,
            heat_j_per_k_wh: $heat,
        };
    )*};
}

cell_models! {
    // rest V at 0, 10, ... 100 %                                r   accept | gas C  at V slope  per K  | eff   | max  nom | J/K Wh
    /// Flooded lead acid. OCV = SG + 0.84 V from SG 1.10 (empty) to 1.28
    /// (full): 1.94 to 2.12 V ("Handbook of Batteries", ch. 23). 6 mOhm for
    /// a 100 Ah cell; the side current 0.06 % C at the 2.27 V float
    /// voltage, doubling every 60 mV (a float current of 0.5-1 mA/Ah, as
    /// chapter 23's float figures), 4 mV/K earlier when warm (the -3 to -5
    /// mV/cell/degC compensation chargers apply, BU-403); 92 % charge
    /// efficiency, so a whole charge takes 105-130 % of the Ah; 2.65 V/cell
    /// at most (equalize goes to 2.58).
    FLOODED:
        [1.94 1.96 1.98 2.00 2.02 2.04 2.06 2.08 2.09 2.11 2.12] 0.6 0.21  | 0.0006 2.27 0.0866 -0.004 | 0.92  | 2.65 2.0 | 26.0;
    /// Valve-regulated lead acid (AGM, gel): the rest voltage 30 mV above
    /// flooded (a stronger acid: 2.15 V/cell full), lower resistance, the
    /// side reaction (oxygen recombination) 0.1 % C at 2.27 V, 95 % charge
    /// efficiency; 2.50 V/cell at most (no equalize: it would dry the cells
    /// out).
    VALVE_REGULATED:
        [1.97 1.99 2.01 2.03 2.05 2.07 2.09 2.11 2.12 2.14 2.15] 0.4 0.18  | 0.001  2.27 0.0866 -0.004 | 0.95  | 2.50 2.0 | 26.0;
    /// Nickel cadmium (vented, pocket plates): rest 1.10 to 1.32 V/cell, the
    /// side reaction (oxygen) 0.2 % C at the 1.40 V float voltage, doubling
    /// every 50 mV, 3 mV/K earlier when warm; 83 % charge efficiency (Saft's
    /// charge factor 1.2-1.4); 1.70 V/cell at most.
    NICKEL_CADMIUM:
        [1.10 1.18 1.22 1.24 1.25 1.26 1.27 1.28 1.29 1.30 1.32] 0.4 0.074 | 0.002  1.40 0.072  -0.003 | 0.83  | 1.70 1.2 | 26.0;
    /// Nickel metal hydride: rest 1.15 to 1.38 V/cell, the side reaction
    /// 0.1 % C at 1.40 V, 88 % charge efficiency (charge input 120-150 %,
    /// "Handbook of Batteries", ch. 30); 1.60 V/cell at most.
    NICKEL_METAL_HYDRIDE:
        [1.15 1.22 1.25 1.27 1.28 1.29 1.30 1.31 1.33 1.35 1.38] 0.4 0.028 | 0.001  1.40 0.072  -0.003 | 0.88  | 1.60 1.2 | 20.0;
    /// Lithium ion (NMC): rest 3.00 to 4.18 V/cell, no side reaction, 99.5 %
    /// efficiency, 4.20 V/cell at most (BU-409); charged below 0 degC it
    /// plates lithium ([`Pack::plated_ah`]).
    LITHIUM_ION:
        [3.00 3.45 3.55 3.62 3.68 3.75 3.83 3.92 4.00 4.08 4.18] 0.2 0.0   | 0.0    4.2  0.1    0.0    | 0.995 | 4.20 3.7 | 8.0;
}

/// The model of `battery_type` (lead acid flooded or valve-regulated,
/// nickel cadmium, nickel metal hydride, lithium ion).
#[must_use]
pub fn cell_model(battery_type: BatteryType) -> Option<&'static CellModel> {
    Some(match battery_type {
        BatteryType::LeadAcid {
            kind: LeadAcid::MaintenanceFree(_),
            ..
        } => &VALVE_REGULATED,
        BatteryType::LeadAcid { .. } => &FLOODED,
        BatteryType::NickelCadmium { .. } => &NICKEL_CADMIUM,
        BatteryType::NickelMetalHydride { .. } => &NICKEL_METAL_HYDRIDE,
        BatteryType::LithiumIon { .. } => &LITHIUM_ION,
        _ => return None,
    })
}

impl CellModel {
    /// The rest voltage at `soc` (0..=1), V.
    #[must_use]
    pub fn rest_voltage(&self, soc: f64) -> f64 {
        let x = soc.clamp(0.0, 1.0) * 10.0;
        let i = (x as usize).min(9);
        let (a, b) = (
            self.ocv.get(i).copied().unwrap_or(0.0),
            self.ocv.get(i + 1).copied().unwrap_or(0.0),
        );
        a + (b - a) * (x - i as f64)
    }

    /// The charge reaction's resistance times capacity at `soc` and
    /// `celsius`, Ohm Ah (infinite when full). Cold raises it: 2 % per
    /// kelvin below 25 degC, at most threefold (ours; the electrolyte's
    /// conductivity falls about so, "Handbook of Batteries", ch. 23).
    fn charge_r_ah(&self, soc: f64, celsius: f64) -> f64 {
        let cold = (1.0 + 0.02 * (25.0 - celsius)).clamp(0.5, 3.0);
        let s = soc.clamp(0.0, 1.0);
        if s >= 1.0 {
            return f64::INFINITY;
        }
        self.r_ah * cold + self.acceptance_ah * s / (1.0 - s)
    }

    /// The side reaction's current at cell voltage `v`, in C.
    fn side_c(&self, v: f64, celsius: f64) -> f64 {
        if self.gas_c <= 0.0 {
            return 0.0;
        }
        let onset = self.gas_v + self.gas_temp_v * (celsius - 25.0);
        self.gas_c * ((v - onset) / self.gas_slope_v).min(40.0).exp()
    }

    /// Both reactions' currents at cell voltage `v`, in C: (charge,
    /// side).
    fn split_c(&self, v: f64, soc: f64, celsius: f64) -> (f64, f64) {
        let r = self.charge_r_ah(soc, celsius);
        let charge = if r.is_finite() {
            (v - self.rest_voltage(soc)) / r
        } else {
            0.0
        };
        (charge, self.side_c(v, celsius))
    }

    /// The cell voltage that takes `c` C (above 0) at `soc`: the root of
    /// charge + side = c, by Newton's method from above (the sum is
    /// increasing and convex in the voltage, so the steps fall onto the
    /// root without passing it).
    fn voltage_for(&self, c: f64, soc: f64, celsius: f64) -> f64 {
        let ocv = self.rest_voltage(soc);
        let r = self.charge_r_ah(soc, celsius);
        // Each reaction alone taking all of it bounds the voltage above.
        let by_charge = if r.is_finite() {
            ocv + c * r
        } else {
            f64::INFINITY
        };
        let by_side = if self.gas_c > 0.0 {
            let onset = self.gas_v + self.gas_temp_v * (celsius - 25.0);
            onset + self.gas_slope_v * (c / self.gas_c).ln()
        } else {
            f64::INFINITY
        };
        let mut v = by_charge.min(by_side);
        if !v.is_finite() {
            // A full lithium cell takes nothing: only the ohmic drop.
            return ocv + c * self.r_ah;
        }
        for _ in 0..30 {
            let (charge, side) = self.split_c(v, soc, celsius);
            let slope = if r.is_finite() { 1.0 / r } else { 0.0 } + side / self.gas_slope_v;
            let excess = charge + side - c;
            if slope <= 0.0 || excess.abs() < 1e-9 {
                break;
            }
            v -= excess / slope;
        }
        v
    }
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
    /// The cell's chemistry ([`cell_model`] of the battery type; a bench
    /// may change its figures).
    pub model: CellModel,
    /// Ohmic resistance of the whole pack at 25 degC (what a discharge
    /// sees), Ohm.
    pub resistance_ohm: f64,
    /// Heat capacity, J/K.
    pub heat_capacity_j_per_k: f64,
    /// Thermal resistance to ambient, K/W.
    pub thermal_resistance_k_per_w: f64,
    /// Ambient temperature, degC.
    pub ambient_c: f64,
}

impl PackSpec {
    /// A pack of `cells` cells of `chemistry` (its first battery type:
    /// flooded for lead acid) and `capacity_ah`, with the chemistry's
    /// [`CellModel`], its thermal mass ([`CellModel::heat_j_per_k_wh`]: a
    /// 48 V 100 Ah lead-acid pack 125 kJ/K, about 140 kg) and 0.1 K/W to a
    /// 25 degC ambient (ours: about 1.5 m² of case at 7 W/(m² K)).
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
        let model = *cell_model(battery_type).ok_or(PackError::UnsupportedChemistry(chemistry))?;
        if cells == 0 || capacity_ah.is_nan() || capacity_ah <= 0.0 {
            return Err(PackError::Empty);
        }
        Ok(PackSpec {
            chemistry,
            battery_type,
            cells,
            capacity_ah,
            model,
            resistance_ohm: f64::from(cells) * model.r_ah / capacity_ah,
            heat_capacity_j_per_k: model.heat_j_per_k_wh
                * model.nominal_v
                * f64::from(cells)
                * capacity_ah,
            thermal_resistance_k_per_w: 0.1,
            ambient_c: 25.0,
        })
    }

    /// The rest voltage of one cell at `soc` (0..=1), V.
    #[must_use]
    pub fn cell_rest_voltage(&self, soc: f64) -> f64 {
        self.model.rest_voltage(soc)
    }

    /// Cells of `chemistry` in a pack of `nominal_volts`: 2.0 V a lead-acid
    /// cell, 1.2 V a nickel one, 3.7 V a lithium-ion one
    /// ([`CellModel::nominal_v`]), rounded (a 48 V system: 24, 40 and 13 cells); 0 for a
    /// chemistry without a model.
    #[must_use]
    pub fn cells_for(chemistry: Chemistry, nominal_volts: f64) -> u16 {
        let Some(model) = cell_model(BatteryType::from_u8(chemistry.code() << 4)) else {
            return 0;
        };
        (nominal_volts / model.nominal_v)
            .round()
            .clamp(0.0, 65535.0) as u16
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
    stored_ah: f64,
    side_ah: f64,
    plated_ah: f64,
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
            stored_ah: 0.0,
            side_ah: 0.0,
            plated_ah: 0.0,
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

    /// Ah charged since the pack was made (all that flowed in).
    #[must_use]
    pub const fn charged_ah(&self) -> f64 {
        self.charged_ah
    }

    /// Of [`charged_ah`](Self::charged_ah), what the pack stored, Ah.
    #[must_use]
    pub const fn stored_ah(&self) -> f64 {
        self.stored_ah
    }

    /// Of [`charged_ah`](Self::charged_ah), what went into the side
    /// reaction (gassing), Ah.
    #[must_use]
    pub const fn side_ah(&self) -> f64 {
        self.side_ah
    }

    /// Charge a lithium-ion pack took below 0 degC (plated lithium: lost
    /// capacity and a risk of internal shorts, BU-410 "Charging at high
    /// and low temperatures"), Ah.
    #[must_use]
    pub const fn plated_ah(&self) -> f64 {
        self.plated_ah
    }

    /// The pack's rest (open-circuit) voltage, V.
    #[must_use]
    pub fn rest_voltage(&self) -> f64 {
        f64::from(self.working_cells()) * self.spec.cell_rest_voltage(self.soc)
    }

    /// The share of the capacity each working cell takes of a pack
    /// current, in C per A (0 with no working cell).
    fn c_per_amp(&self) -> f64 {
        if self.working_cells() == 0 {
            return 0.0;
        }
        1.0 / self.spec.capacity_ah
    }

    /// The terminal voltage while `current_a` flows in, V (a discharge:
    /// the rest voltage less the ohmic drop).
    #[must_use]
    pub fn terminal_voltage(&self, current_a: f64) -> f64 {
        let n = f64::from(self.working_cells());
        if current_a <= 0.0 || n == 0.0 {
            return self.rest_voltage() + current_a * self.resistance();
        }
        let c = current_a * self.c_per_amp();
        n * self.spec.model.voltage_for(c, self.soc, self.temperature_c)
    }

    /// The resistance between the terminals (the working cells'), Ohm.
    fn resistance(&self) -> f64 {
        self.spec.resistance_ohm * self.working_share()
    }

    /// The current that holds the terminals at `volts` (0 when the pack is
    /// above it), A.
    #[must_use]
    pub fn current_at(&self, volts: f64) -> f64 {
        let n = self.working_cells();
        if n == 0 {
            // Every cell shorted: a dead short takes what the source gives.
            return if volts > 0.0 { f64::MAX } else { 0.0 };
        }
        let v = volts / f64::from(n);
        let (charge, side) = self.spec.model.split_c(v, self.soc, self.temperature_c);
        ((charge + side) * self.spec.capacity_ah).max(0.0)
    }

    /// `current_a` flowed in for `seconds`: the charge stored (the charge
    /// reaction's share, times its efficiency), the side reaction's, and
    /// the heat (every watt in that is not stored, less what the pack
    /// loses to ambient).
    pub fn step(&mut self, seconds: f64, current_a: f64) {
        let hours = seconds / 3600.0;
        let model = self.spec.model;
        let heat_w = if current_a > 0.0 && self.working_cells() > 0 {
            let n = f64::from(self.working_cells());
            let c = current_a * self.c_per_amp();
            let v = model.voltage_for(c, self.soc, self.temperature_c);
            let side = model.side_c(v, self.temperature_c).min(c);
            let charge_a = (c - side) * self.spec.capacity_ah;
            let stored_a = charge_a * model.efficiency;
            self.stored_ah += stored_a * hours;
            self.side_ah += side * self.spec.capacity_ah * hours;
            if self.spec.chemistry == Chemistry::LithiumIon && self.temperature_c < 0.0 {
                self.plated_ah += charge_a * hours;
            }
            self.soc = (self.soc + stored_a * hours / self.spec.capacity_ah).clamp(0.0, 1.0);
            (current_a * v - stored_a * model.rest_voltage(self.soc)) * n
        } else {
            self.soc = (self.soc + current_a * hours / self.spec.capacity_ah).clamp(0.0, 1.0);
            current_a * current_a * self.resistance()
        };
        self.charged_ah += current_a * hours;
        let loss_w =
            (self.temperature_c - self.spec.ambient_c) / self.spec.thermal_resistance_k_per_w;
        self.temperature_c += (heat_w - loss_w) * seconds / self.spec.heat_capacity_j_per_k;
    }
}

#[cfg(test)]
#[path = "pack_tests.rs"]
mod tests;
