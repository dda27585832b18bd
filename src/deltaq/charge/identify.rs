//! The battery the charge control charges: what the battery module says
//! of it in 6020h (CiA 418 section 7.2.1, battery parameters: sub 1 the
//! battery type, sub 2 the Ah capacity, sub 4 the number of cells), and
//! the algorithm chosen for it ([`algorithm::select`]).
//!
//! The Delta-Q IC Series CANopen interface specification is silent on the
//! charger reading 6020h; what follows is ours. In every mode but
//! monitoring a charger with no permanent algorithm
//! ([`ChargeConfig::permanent_algorithm`](super::ChargeConfig) `None`,
//! and none stored by a 2241h write with bit 31) asks the module for its
//! battery when it finds it ([`Charger`](crate::deltaq::Charger)): while
//! the answer is [`Identification::Pending`] a BMS that says ready does
//! not start a local cycle (a remote BMS's set points do not wait); a
//! [`Identification::Known`] battery makes the table's algorithm for its
//! type and cells active (none fits: none is active, in local mode
//! E-0-2-0 "active algorithm not set", rather than another chemistry's
//! curve; in remote mode the charger's maximum voltage is then the
//! high-voltage threshold); a [`Identification::Failed`] read keeps the active
//! algorithm or, with none, makes the no-CAN algorithm
//! ([`ChargeConfig::no_can_algorithm`](super::ChargeConfig)) active. A
//! choice is made only while no cycle runs (idle, CAN hold-off,
//! terminated): a cycle under way keeps its algorithm until it ends. The
//! capacity feeds the charger's state-of-charge estimate (6080h).

use super::algorithm;
use super::{ChargeControl, ChargePhase};
use crate::clock::Timestamp;

/// The battery as the module describes it in 6020h (CiA 418 section
/// 7.2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BatteryIdentity {
    /// 6020h sub 1, battery type (`cccc wxyz`, CiA 418 appendix A).
    pub battery_type: u8,
    /// 6020h sub 2, Ah capacity (1 Ah; 0: not given).
    pub capacity_ah: u16,
    /// 6020h sub 4, number of cells in series.
    pub cells: u16,
}

/// Where the charger's question about the battery stands
/// ([`ChargeControl::handle_identification`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Identification {
    /// Not asked, or the question was dropped (the module lost or reset).
    Unknown,
    /// Asked; no answer yet: a local cycle does not start meanwhile.
    Pending,
    /// The module answered.
    Known(BatteryIdentity),
    /// The module aborted or did not answer.
    Failed,
}

impl ChargeControl {
    /// The charger's question about the battery (6020h, CiA 418 section
    /// 7.2.1) stands at `id`: while [`Identification::Pending`] a ready BMS
    /// does not start a local cycle; when no permanent algorithm is set and
    /// no cycle runs (idle, hold-off, terminated), a known battery makes
    /// the table's algorithm for it active
    /// ([`select`](super::algorithm::select); none fits: none, E-0-2-0),
    /// and a failed read keeps the active one or, with none, makes the
    /// no-CAN algorithm active. Ours: the Delta-Q IC Series CANopen
    /// interface specification is silent on 6020h.
    pub fn handle_identification(&mut self, now: Timestamp, id: Identification) {
        self.integrate(now);
        let free = self.permanent.is_none()
            && matches!(
                self.phase,
                ChargePhase::Idle | ChargePhase::HoldOff | ChargePhase::Terminated
            );
        match id {
            Identification::Known(b) if free => {
                let table = self.config.algorithms;
                self.active = algorithm::select(table, b.battery_type, b.cells).map(|a| a.id);
                self.incompatible = false;
            }
            Identification::Failed if free => {
                self.active = self.active.or(self.config.no_can_algorithm);
            }
            _ => {}
        }
        self.identity = id;
        self.step(now);
    }

    /// The charger's question about the battery and its answer.
    #[must_use]
    pub const fn identification(&self) -> Identification {
        self.identity
    }

    /// The permanent algorithm (the configuration's, or one a 2241h write
    /// stored with bit 31).
    #[must_use]
    pub const fn permanent_algorithm(&self) -> Option<u16> {
        self.permanent
    }

    /// The algorithm local mode charges with without a BMS.
    pub(super) fn no_can_algorithm(&self) -> Option<u16> {
        self.config
            .no_can_algorithm
            .or(self.active)
            .filter(|id| self.config.algorithm(*id).is_some())
    }

    /// The module is asked for its battery: a local cycle waits.
    pub(super) const fn identifying(&self) -> bool {
        matches!(self.identity, Identification::Pending)
    }

    /// The capacity the module gave (6020h sub 2), Ah; 0 unknown.
    pub(super) const fn capacity_ah(&self) -> u32 {
        match self.identity {
            Identification::Known(b) => b.capacity_ah as u32,
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{bms, control, s};
    use super::super::PowerStage;
    use super::*;
    use crate::deltaq::OperatingMode;

    /// AC on, the battery at `mv` giving `ma`.
    fn output(mv: i32, ma: u32) -> PowerStage {
        PowerStage {
            ac_mv: PowerStage::AC_NOMINAL_MV,
            voltage_mv: mv,
            current_ma: ma,
            ..PowerStage::OFF
        }
    }

    /// The module's answer: 6020h sub 1, sub 2 and sub 4.
    const fn known(battery_type: u8, capacity_ah: u16, cells: u16) -> Identification {
        Identification::Known(BatteryIdentity {
            battery_type,
            capacity_ah,
            cells,
        })
    }

    #[test]
    fn a_pending_question_holds_the_start_and_the_answer_chooses() {
        let mut c = ChargeControl::new(
            OperatingMode::Local,
            super::super::ChargeConfig {
                permanent_algorithm: None,
                ..super::super::ChargeConfig::example()
            },
        );
        c.handle_identification(s(0), Identification::Pending);
        c.handle_bus(s(0), bms(0));
        c.handle_power_stage(s(0), output(50_000, 0));
        assert_eq!(c.phase(), ChargePhase::Idle);
        assert!(c.alarms().is_empty(), "no E-0-2-0 while asking");
        c.handle_identification(s(1), known(0x80, 80, 40));
        assert_eq!(c.active_algorithm(), Some(31));
        assert_eq!(c.phase(), ChargePhase::Bulk);
        assert_eq!(c.capacity_ah(), 80);
        // A new answer while the cycle runs changes nothing until it ends.
        let li = known(0xA0, 100, 13);
        c.handle_identification(s(2), li);
        assert_eq!(c.active_algorithm(), Some(31));
        // With a permanent algorithm (the example's 1) an answer changes
        // nothing.
        let mut c = control(OperatingMode::Local);
        c.handle_identification(s(0), li);
        assert_eq!(c.active_algorithm(), Some(1));
    }

    #[test]
    fn the_charger_soc_is_its_own_estimate_and_100_only_at_the_end() {
        let mut c = control(OperatingMode::Local);
        c.handle_bus(s(0), bms(0));
        // No cycle yet, no module figure: unknown.
        assert_eq!(c.status().charger_soc, 0xFF);
        c.handle_identification(s(0), known(0x10, 100, 24));
        // A flooded pack at rest at 2.03 V/cell: half full.
        c.handle_power_stage(s(0), output(24 * 2030, 0));
        assert_eq!(c.phase(), ChargePhase::Bulk);
        assert_eq!(c.status().charger_soc, 50);
        // An hour at 25 A: 25 Ah, 90 % of it stored in 100 Ah: 72 %.
        c.handle_power_stage(s(1), output(51_000, 25_000));
        c.handle_power_stage(s(3601), output(55_000, 25_000));
        assert_eq!(c.status().ah_returned, 200);
        assert_eq!(c.status().charger_soc, 72);
        // Absorption is not "80 % and up" by phase: still the estimate.
        c.handle_power_stage(s(3602), output(58_800, 25_000));
        assert_eq!(c.phase(), ChargePhase::Absorption);
        assert_eq!(c.status().charger_soc, 72);
    }
}
