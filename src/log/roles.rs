//! Which node is which ([`Roles`]): given, or learned from the SDO
//! transfers of the log and the EDS files read.

use std::prelude::rust_2021::*;

use crate::od::index::{DEVICE_TYPE, IDENTITY};
use crate::NodeId;

use crate::log::sdo;

/// Which node is which, for naming Delta-Q codes and roles. A node has a
/// role only from evidence: `--charger-node` / `--battery-node`, its device
/// type (1000h) read by SDO in the log or given by its EDS naming profile
/// 419 (a charger) or 418 (a battery module). A charger is a Delta-Q
/// charger (Delta-Q object names, error labels and default PDOs) only with
/// Delta-Q evidence: `--charger-node`, an EDS whose vendor ID (1018h:01 or
/// `VendorNumber`) is Delta-Q's, or that vendor ID read by SDO in the log;
/// otherwise it is a CiA 419 charger, named with the CiA 419 objects only.
#[derive(Clone, Copy, Debug, Default)]
pub struct Roles {
    /// The charger (Delta-Q or CiA 419).
    pub charger: Option<NodeId>,
    /// The CiA 418 battery module.
    pub battery: Option<NodeId>,
    /// The node known to be a Delta-Q device.
    pub deltaq: Option<NodeId>,
}

/// Delta-Q's vendor ID (1018h sub 1).
pub(super) const DELTAQ_VENDOR_ID: u32 = crate::deltaq::VENDOR_ID;

impl Roles {
    /// `charger`, `battery` or nothing, for `node`.
    pub fn role(&self, node: Option<NodeId>) -> Option<&'static str> {
        match node {
            Some(n) if Some(n) == self.charger => Some("charger"),
            Some(n) if Some(n) == self.battery => Some("battery"),
            _ => None,
        }
    }

    /// The nodes of the bundled session and of the real Delta-Q captures
    /// (tests/data/CAPTURES.md): the Delta-Q charger 10 and the battery
    /// module 1, unless given.
    pub fn demo(&mut self) {
        self.charger = self.charger.or(NodeId::new(10));
        self.battery = self.battery.or(NodeId::new(1));
        self.deltaq = self.deltaq.or(self.charger);
    }

    /// True when `node` is the charger (Delta-Q or CiA 419).
    pub fn is_charger(&self, node: NodeId) -> bool {
        self.charger == Some(node)
    }

    /// True when `node` is the charger and a Delta-Q one.
    pub fn is_deltaq_charger(&self, node: NodeId) -> bool {
        self.is_charger(node) && self.deltaq == Some(node)
    }

    /// True when `node` is the battery module (and not also the charger).
    pub fn is_battery(&self, node: NodeId) -> bool {
        self.battery == Some(node) && self.charger != Some(node)
    }

    /// Learns from a completed upload: of 1000h (device type) a role, the
    /// profile number in bits 0-15, 418 a battery module, 419 a charger; of
    /// 1018h sub 1 (vendor ID) Delta-Q's, that the node is a Delta-Q
    /// device (a charger, unless it has another role). Roles given on the
    /// command line or learned before are kept. Returns what was learned,
    /// in words.
    pub fn learn(&mut self, report: &sdo::Report) -> Option<String> {
        if !matches!(report.end, sdo::End::Complete)
            || !matches!(report.direction, sdo::Direction::Upload)
        {
            return None;
        }
        match (report.index, report.sub, &report.bytes[..]) {
            (DEVICE_TYPE, 0, [a, b, ..]) => {
                let (name, given) =
                    self.give_by_profile(report.node, u16::from_le_bytes([*a, *b]))?;
                given.then(|| format!("the {name} (its device type, {DEVICE_TYPE:04X}h, says so)"))
            }
            (IDENTITY, 1, [a, b, c, d]) => {
                let vendor = u32::from_le_bytes([*a, *b, *c, *d]);
                self.give_deltaq(report.node, vendor).then(|| {
                    format!(
                        "a Delta-Q device (its vendor ID, {IDENTITY:04X}h:01, is {vendor:08X}h)"
                    )
                })
            }
            _ => None,
        }
    }

    /// Makes `node` the Delta-Q device when `vendor` is Delta-Q's vendor ID
    /// and no other node is; it becomes the charger unless it has a role.
    /// True when this changed anything.
    pub(super) fn give_deltaq(&mut self, node: NodeId, vendor: u32) -> bool {
        if vendor != DELTAQ_VENDOR_ID || self.deltaq.is_some_and(|d| d != node) {
            return false;
        }
        let before = (self.charger, self.deltaq);
        self.deltaq = Some(node);
        if self.charger.is_none() && self.battery != Some(node) {
            self.charger = Some(node);
        }
        before != (self.charger, self.deltaq)
    }

    /// The role a device type's profile (bits 0-15 of 1000h) names, 418 a
    /// battery module and 419 a charger, given to `node` unless another
    /// node has it already: the role's name and whether it was given.
    pub(super) fn give_by_profile(
        &mut self,
        node: NodeId,
        profile: u16,
    ) -> Option<(&'static str, bool)> {
        let (slot, name) = match profile {
            418 => (&mut self.battery, "battery"),
            419 => (&mut self.charger, "charger"),
            _ => return None,
        };
        let given = slot.is_none();
        if given {
            *slot = Some(node);
        }
        Some((name, given))
    }
}
