//! PDO mappings for the decoder: `--pdo COBID=INDEX:SUB:BITS,...`, the
//! bundled capture's mapping (`--pdo-capture-mapping`) and the defaults.

use canopen_codec::cia418::BATTERY_MODULE_CATALOGUE;
use canopen_codec::cia419::CHARGER_CATALOGUE as CIA419_CATALOGUE;
use canopen_codec::cob_id::classify_standard;
use canopen_codec::deltaq::{default_mapping_for_cob_id, CHARGER_CATALOGUE};
use canopen_codec::pdo::{Catalogue, MappingEntry, NamedFields, PdoMapping, MAX_ENTRIES};
use canopen_codec::NodeId;
use canopen_codec::{CanFrame, CanId, Message};

use crate::pdo_learn::{Learned, Origin};
use crate::Roles;

/// The objects of a node with no role: CiA 301 names nothing in a PDO, so
/// fields print as index, sub-index and raw value.
use crate::sdo_value::NO_CATALOGUE;

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

/// The mapping of the real capture, from tests/data/CAPTURES.md, in
/// `--pdo` syntax. Unnamed padding uses CiA 301 dummy entries (0005h
/// UNSIGNED8, 0006h UNSIGNED16). 0x28A's layout is not published: it stays
/// unmapped (raw).
pub const CAPTURE_PDOS: [&str; 4] = [
    "18A=2002:0:16,2101:0:16,2006:0:16,6:0:16",
    "38A=2060:0:32,2200:0:16,6080:0:8,5:0:8",
    "20A=2FFA:1:8,6081:0:8,4201:0:8,2276:0:16,6070:0:16,6000:0:8",
    "30A=2FFA:1:8,2FFA:1:8,2002:0:16,2101:0:16,6010:0:16",
];

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
    pub given: Vec<(u16, PdoMapping)>,
    pub defaults: bool,
}

fn hex<T: TryFrom<u32>>(s: &str, what: &str, max: u32) -> Result<T, String> {
    let digits = s
        .strip_prefix("0x")
        .or_else(|| s.strip_prefix("0X"))
        .unwrap_or(s);
    u32::from_str_radix(digits, 16)
        .ok()
        .filter(|v| *v <= max && !digits.starts_with('+'))
        .and_then(|v| T::try_from(v).ok())
        .ok_or(format!("{what} '{s}' is not hex 0..={max:X}"))
}

/// Parses `COBID=INDEX:SUB:BITS,...`.
pub fn parse_pdo(arg: &str) -> Result<(u16, PdoMapping), String> {
    let fail = |why: String| format!("--pdo '{arg}': {why}");
    let (cob, list) = arg
        .split_once('=')
        .ok_or_else(|| fail("expected COBID=INDEX:SUB:BITS,...".into()))?;
    let cob_id: u16 = hex(cob.trim(), "COB-ID", 0x7FF).map_err(fail)?;
    let mut entries = Vec::new();
    for item in list.split(',') {
        let parts: Vec<&str> = item.trim().split(':').collect();
        let [index, sub, bits] = parts[..] else {
            return Err(fail(format!(
                "entry '{item}' is not INDEX:SUB:BITS (hex:hex:decimal)"
            )));
        };
        let index: u16 = hex(index, "index", 0xFFFF).map_err(fail)?;
        let sub: u8 = hex(sub, "sub-index", 0xFF).map_err(fail)?;
        let bits: u8 = bits
            .parse()
            .ok()
            .filter(|b| (1..=64).contains(b))
            .ok_or_else(|| fail(format!("bits '{bits}' is not a decimal 1..=64")))?;
        entries.push(MappingEntry::new(index, sub, bits));
    }
    if entries.len() > MAX_ENTRIES {
        return Err(fail(format!(
            "{} entries, at most {MAX_ENTRIES}",
            entries.len()
        )));
    }
    let mapping = PdoMapping::new(&entries).map_err(|e| fail(e.to_string()))?;
    Ok((cob_id, mapping))
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
