//! PDO mappings for the decoder: `--pdo COBID=INDEX:SUB:BITS,...`, the
//! bundled capture's mapping (`--pdo-capture-mapping`) and the defaults.
//!
//! A PDO's bytes mean nothing without its mapping, so the decoder takes it
//! as configuration:
//!
//! - `--pdo COBID=INDEX:SUB:BITS,...` (repeatable, one COB-ID each) gives
//!   the mapping of the PDO on identifier COBID: COBID, INDEX and SUB in hex
//!   (`18A` or `0x18A`), BITS in decimal, entries in mapping order. Dummy
//!   entries (index 1..1F, e.g. `6:0:16`) and 2FFAh are padding. The
//!   objects are named from the dictionary of the node the COB-ID belongs
//!   to, as far as the evidence says whose it is: its EDS, else the battery
//!   node's CiA 418, a Delta-Q charger's Delta-Q and CiA 418 objects, a
//!   CiA 419 charger's CiA 418/419 objects; a node without a role or EDS
//!   names nothing (`2002h unknown object: raw 1374h (16 bits)`). An entry
//!   mapped with fewer bits than its object is read from those bits
//!   (sign-extended for a signed object) and flagged `[deviates: mapped as
//!   4 bits, object has 8]`.
//! - Without `--pdo` for a COB-ID, the defaults apply to nodes with a role:
//!   the Delta-Q charger's default PDOs on a Delta-Q charger's COB-IDs, the
//!   CiA 418 battery-module defaults on the battery module's. A node has a
//!   role only from evidence: `--charger-node` / `--battery-node`, its
//!   EDS's 1000h, or its 1000h read by SDO in the log (profile 419:
//!   charger, 418: battery module; reported on a line of its own). A charger
//!   is a Delta-Q one only with Delta-Q evidence: `--charger-node`, an EDS
//!   with Delta-Q's vendor ID, or 1018h:01 read in the log with Delta-Q's
//!   vendor ID (00000110h; reported on a line of its own; in JSON each
//!   fact learned is `{"kind":"role","node","role","deltaq","text"}`).
//!   `--pdo-capture-mapping` and the bundled session imply the Delta-Q
//!   charger 10 and battery module 1. `--no-default-pdos` turns the
//!   defaults off. A frame with no known mapping is printed raw, as before.
//! - `--pdo-capture-mapping` decodes the real Delta-Q captures (third-party
//!   data, not in this repository; see tests/data/CAPTURES.md): it adds the
//!   mapping of tests/data/CAPTURES.md (the integrator remapped that
//!   charger) and implies `--no-default-pdos`; 0x28A, whose layout is not
//!   published, stays raw. It is the same as
//!
//! ```text
//! canopen-decode --no-default-pdos \
//!     --pdo 18A=2002:0:16,2101:0:16,2006:0:16,6:0:16 \
//!     --pdo 38A=2060:0:32,2200:0:16,6080:0:8,5:0:8 \
//!     --pdo 20A=2FFA:1:8,6081:0:8,4201:0:8,2276:0:16,6070:0:16,6000:0:8 \
//!     --pdo 30A=2FFA:1:8,2FFA:1:8,2002:0:16,2101:0:16,6010:0:16 \
//!     deltaq-icl1500-charging.log
//! ```
//!
//! In words, the fields follow the frame after ` = `, numbers **rounded to
//! at most 2 decimals** with trailing zeros dropped (halves away from zero:
//! 0x1374/256 A prints `19.45 A`, 0x07BA/16 V `123.63 V`, 0x5200/256 V
//! `82 V`), padding left out, and
//! `(+N unmapped bytes)` when the frame is longer than its mapping; a
//! default mapping is labelled `[charger default]` / `[battery default]`.
//! In `--json` the frame gets `mapping` (`given`, `charger default`,
//! `battery default`), `unmapped_bytes` and `fields`: one object per entry
//! with `index`, `sub`, `bits`, `name`, `raw`, `kind` (`scaled`, `flags`,
//! `invalid`, `no_value`, `padding`, `missing`, `raw`, ...), `value` (the
//! **exact** number for scaled values, e.g. 19.453125; words for bit fields
//! and codes; null otherwise), `unit` where the object has one, and `text`.
//!
//! 6010h temperature is decoded per CiA 418 (0.125 degC/bit, no offset):
//! the capture README's DBC adds -40 degC, which the profile does not have.

use crate::cia418::BATTERY_MODULE_CATALOGUE;
use crate::cia419::CHARGER_CATALOGUE as CIA419_CATALOGUE;
use crate::cob_id::classify_standard;
use crate::deltaq::{default_mapping_for_cob_id, CHARGER_CATALOGUE};
use crate::pdo::{Catalogue, NamedFields, PdoMapping};
use crate::NodeId;
use crate::{CanFrame, CanId, Message};
use std::prelude::rust_2021::*;

use crate::log::pdo_learn::{Learned, Origin};
pub use crate::log::pdo_syntax::{parse_pdo, CAPTURE_PDOS};
use crate::log::Roles;

/// The objects of a node with no role: CiA 301 names nothing in a PDO, so
/// fields print as index, sub-index and raw value.
use crate::log::sdo_value::NO_CATALOGUE;

/// The catalogue whose names a PDO of `node` gets: its EDS's, else its
/// role's (the Delta-Q charger's only with Delta-Q evidence, a CiA 419
/// charger's the CiA 419 objects), else none (no name is guessed).
pub fn catalogue_of(node: Option<NodeId>, roles: &Roles, learned: &Learned) -> Catalogue {
    let Some(node) = node else {
        return NO_CATALOGUE;
    };
    if let Some(c) = learned.catalogue(node) {
        c
    } else if roles.is_battery(node) {
        BATTERY_MODULE_CATALOGUE
    } else if roles.is_deltaq_charger(node) {
        CHARGER_CATALOGUE
    } else if roles.is_charger(node) {
        CIA419_CATALOGUE
    } else {
        NO_CATALOGUE
    }
}

/// Where a frame's mapping came from.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// `--pdo` or `--pdo-capture-mapping`.
    Given,
    /// The Delta-Q charger's default for the charger node's COB-IDs.
    ChargerDefault,
    /// The CiA 418 default for the battery node's COB-IDs.
    BatteryDefault,
    /// Written or read by SDO earlier in the log.
    Learned,
    /// The node's EDS or DCF (`--eds`).
    Eds,
}

impl Source {
    /// `given`, `charger default`, `battery default`, `learned`, ...: the JSON `mapping` key.
    pub fn name(self) -> &'static str {
        match self {
            Source::Given => "given",
            Source::ChargerDefault => "charger default",
            Source::BatteryDefault => "battery default",
            Source::Learned => "from SDO in the log",
            Source::Eds => "from the EDS",
        }
    }
}

/// The mappings the user gave, and whether the defaults apply.
#[derive(Clone)]
pub struct Mappings {
    /// The mappings given (`--pdo`), by COB-ID.
    pub given: Vec<(u16, PdoMapping)>,
    /// The default PDOs apply to nodes with a role (not with `--no-default-pdos`).
    pub defaults: bool,
}

impl Mappings {
    /// Adds a `--pdo` mapping; a COB-ID given twice is an error.
    pub fn add(&mut self, arg: &str) -> Result<(), String> {
        let (cob_id, mapping) = parse_pdo(arg)?;
        if self.given.iter().any(|(id, _)| *id == cob_id) {
            return Err(format!("--pdo: COB-ID {cob_id:03X} given twice"));
        }
        self.given.push((cob_id, mapping));
        Ok(())
    }

    /// Adds the capture's mapping for COB-IDs not given with `--pdo`, and
    /// turns the defaults off (this charger was remapped).
    pub fn add_capture(&mut self) -> Result<(), String> {
        for spec in CAPTURE_PDOS {
            let (cob_id, mapping) = parse_pdo(spec)?;
            if !self.given.iter().any(|(id, _)| *id == cob_id) {
                self.given.push((cob_id, mapping));
            }
        }
        self.defaults = false;
        Ok(())
    }

    /// The named fields of a PDO (or unclassified data) frame, if a mapping
    /// is known for its identifier.
    pub fn fields(
        &self,
        frame: &CanFrame,
        msg: &Message,
        roles: &Roles,
        learned: &Learned,
    ) -> Option<(Source, NamedFields)> {
        let (source, catalogue, mapping) = self.mapping(frame, msg, roles, learned)?;
        Some((source, catalogue.decode(&mapping, frame.data())))
    }

    /// The mapping that applies to a PDO (or unclassified data) frame, where
    /// it came from and the catalogue that names its objects; the one place
    /// that decides it (the frame outputs, `--signals` and `--dbc` use it).
    pub fn mapping(
        &self,
        frame: &CanFrame,
        msg: &Message,
        roles: &Roles,
        learned: &Learned,
    ) -> Option<(Source, Catalogue, PdoMapping)> {
        let CanId::Standard(id) = frame.id() else {
            return None;
        };
        if frame.is_remote()
            || !matches!(
                msg,
                Message::Tpdo { .. } | Message::Rpdo { .. } | Message::Unknown(_)
            )
        {
            return None;
        }
        let given = self.given.iter().find(|(g, _)| *g == id);
        if let (None, Some((node, m, origin))) = (given, learned.mapping(id)) {
            let cat = catalogue_of(Some(node), roles, learned);
            let source = match origin {
                Origin::Eds => Source::Eds,
                Origin::Log => Source::Learned,
            };
            return Some((source, cat, m));
        }
        match given {
            Some((_, m)) => {
                // A mapping names objects of the dictionary of the node the
                // COB-ID belongs to, as far as the evidence says whose it is.
                let cat = catalogue_of(classify_standard(id).node(), roles, learned);
                Some((Source::Given, cat, *m))
            }
            None if self.defaults => {
                // Defaults only for a node with a role; the charger's are
                // Delta-Q's, so only for a Delta-Q charger.
                let node = classify_standard(id).node()?;
                let other = NodeId::new(node.raw() % 127 + 1)?;
                let (charger, battery) = if roles.is_deltaq_charger(node) {
                    (node, other)
                } else if roles.is_battery(node) {
                    (other, node)
                } else {
                    return None;
                };
                let (cat, m) = default_mapping_for_cob_id(id, charger, battery)?;
                let source = if cat == BATTERY_MODULE_CATALOGUE {
                    Source::BatteryDefault
                } else {
                    Source::ChargerDefault
                };
                Some((source, cat, m))
            }
            None => None,
        }
    }
}
