//! PDO configuration learned from the log: SDO transfers of the PDO
//! communication and mapping parameters (CiA 301 section 7.4.8, objects
//! 1400h-15FFh RPDO communication, 1600h-17FFh RPDO mapping, 1800h-19FFh
//! TPDO communication, 1A00h-1BFFh TPDO mapping), written or read, apply to
//! the PDOs that follow.
//!
//! - Sub-index 1 of a communication parameter is the COB-ID (bit 31 set:
//!   the PDO is not valid; bit 29: a 29-bit identifier, which the decoder
//!   does not map).
//! - Sub-index 0 of a mapping parameter is the number of entries, sub 1..=8
//!   the entries (index << 16 | sub << 8 | bits). The CiA 301 procedure
//!   writes 0 first, then the entries, then the number: the mapping applies
//!   when a number 1..=8 is written (or read) with its entries known, and
//!   stops applying when 0 is.
//! - A PDO whose COB-ID the log has not shown uses the pre-defined one
//!   (PDOs 0..=3: TPDO 180h/280h/380h/480h + node, RPDO 200h.. + node).

use std::collections::HashMap;
use std::prelude::rust_2021::*;

use crate::eds::{DataType, Eds};
use crate::od::index::{
    RPDO_COMMUNICATION, RPDO_COMMUNICATION_LAST, RPDO_MAPPING, RPDO_MAPPING_LAST,
    TPDO_COMMUNICATION, TPDO_COMMUNICATION_LAST, TPDO_MAPPING, TPDO_MAPPING_LAST,
};
use crate::od::{Access, Address, ObjectRow};
use crate::pdo::{Catalogue, MappingEntry, PdoMapping, MAX_ENTRIES};
use crate::NodeId;

use crate::log::sdo::{End, Report};

/// One PDO of one node as the log shows it.
#[derive(Default, Clone, Copy)]
struct Pdo {
    /// The COB-ID from sub-index 1, when seen.
    cob_id: Option<u32>,
    /// The mapping entries seen, by sub-index 1..=8.
    entries: [Option<u32>; MAX_ENTRIES],
    /// The mapping in force and the identifier it applies to.
    active: Option<(u16, PdoMapping)>,
}

/// Which PDO: its node, transmit (true) or receive, its number from 0.
type Key = (NodeId, bool, u16);

/// Where a PDO's configuration came from.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Origin {
    /// An EDS or DCF given with `--eds`.
    Eds,
    /// SDO transfers in the log.
    Log,
}

/// The PDO configuration learned from the log (and the `--eds` files).
#[derive(Default)]
pub struct Learned {
    /// The objects of a node with an EDS: its own names first, then the
    /// profile's catalogue for its role.
    catalogues: HashMap<NodeId, Catalogue>,
    pdos: HashMap<Key, Pdo>,
    /// Identifier -> the PDO whose mapping applies there, and the origin.
    by_id: HashMap<u16, (Key, PdoMapping, Origin)>,
}

fn name((node, tx, n): Key) -> String {
    format!("{}{n} of node {node}", if tx { "TPDO" } else { "RPDO" })
}

/// The pre-defined COB-ID of PDO `n` of `node` (CiA 301 pre-defined
/// connection set), for PDOs 0..=3.
fn predefined((node, tx, n): Key) -> Option<u16> {
    let base: u16 = if tx { 0x180 } else { 0x200 };
    (n < 4).then(|| base + 0x100 * n + u16::from(node.raw()))
}

impl Learned {
    /// The mapping learned for frames on `id`, the node whose PDO it is,
    /// and where the mapping came from.
    pub fn mapping(&self, id: u16) -> Option<(NodeId, PdoMapping, Origin)> {
        self.by_id
            .get(&id)
            .map(|((node, ..), m, o)| (*node, *m, *o))
    }

    /// The catalogue of `node`'s objects built from its EDS, if one was given.
    pub fn catalogue(&self, node: NodeId) -> Option<Catalogue> {
        self.catalogues.get(&node).copied()
    }

    /// Names `node`'s objects from its EDS (`--eds`): every variable of a
    /// data type a PDO can carry gets the EDS's name and a plain integer or
    /// text reading; `profile`'s tables (the CiA 418 or Delta-Q catalogue
    /// for a node with a role) are searched first, for their units. The
    /// tables live as long as the program (built once per `--eds`).
    pub fn name_objects(&mut self, node: NodeId, eds: &Eds, profile: Option<Catalogue>) {
        let mut own = Vec::new();
        for (index, sub, name, data_type) in eds_variables(eds) {
            // Plain integers of the types a PDO can carry (a BOOLEAN is
            // mapped as 1 bit, the others at their size).
            if !(data_type.is_signed() || data_type.is_unsigned() || data_type == DataType::Boolean)
                || data_type.fixed_size().is_none_or(|n| n > 8)
            {
                continue;
            }
            let name: &'static str = Box::leak(name.into_boxed_str());
            // Access and mapping are the node's business; the decoder reads
            // the name and the type.
            own.push(ObjectRow::new(
                Address::new(index, sub),
                name,
                data_type,
                Access::ReadWrite,
            ));
        }
        let own: &'static [ObjectRow] = Box::leak(own.into_boxed_slice());
        let mut tables: Vec<&'static [ObjectRow]> =
            profile.map(|c| c.tables().to_vec()).unwrap_or_default();
        tables.push(own);
        let tables: &'static [&'static [ObjectRow]] = Box::leak(tables.into_boxed_slice());
        self.catalogues
            .insert(node, Catalogue::new("the node's EDS", tables));
    }

    /// A PDO as a device description gives it (`--eds`): its COB-ID
    /// (`raw`, the Unsigned32 of sub-index 1) and its mapping entries.
    /// Returns the identifier its mapping now applies to.
    pub fn preset(
        &mut self,
        node: NodeId,
        tx: bool,
        number: u16,
        cob_id: Option<u32>,
        entries: &[MappingEntry],
    ) -> Option<u16> {
        let key: Key = (node, tx, number);
        let pdo = self.pdos.entry(key).or_default();
        pdo.cob_id = cob_id;
        for (slot, e) in pdo.entries.iter_mut().zip(entries) {
            *slot = Some(e.to_u32());
        }
        let mapping = PdoMapping::new(entries)
            .ok()
            .filter(|m| !m.entries().is_empty())?;
        let id = self.id_of(key).ok()?;
        self.deactivate(key);
        if let Some(p) = self.pdos.get_mut(&key) {
            p.active = Some((id, mapping));
        }
        self.by_id.insert(id, (key, mapping, Origin::Eds));
        Some(id)
    }

    /// Takes a finished transfer; says how it changed a PDO, if it did.
    pub fn transfer(&mut self, r: &Report) -> Option<String> {
        if r.end != End::Complete {
            return None;
        }
        let (tx, comm, base) = match r.index {
            RPDO_COMMUNICATION..=RPDO_COMMUNICATION_LAST => (false, true, RPDO_COMMUNICATION),
            RPDO_MAPPING..=RPDO_MAPPING_LAST => (false, false, RPDO_MAPPING),
            TPDO_COMMUNICATION..=TPDO_COMMUNICATION_LAST => (true, true, TPDO_COMMUNICATION),
            TPDO_MAPPING..=TPDO_MAPPING_LAST => (true, false, TPDO_MAPPING),
            _ => return None,
        };
        let key: Key = (r.node, tx, r.index - base);
        let pdo = self.pdos.entry(key).or_default();
        let u32_value = match r.bytes[..] {
            [a, b, c, d, ..] => Some(u32::from_le_bytes([a, b, c, d])),
            _ => None,
        };
        if comm {
            if r.sub != 1 {
                return None;
            }
            let raw = u32_value?;
            pdo.cob_id = Some(raw);
            return Some(self.moved(key));
        }
        match r.sub {
            0 => {
                let count = *r.bytes.first()?;
                Some(self.remap(key, count))
            }
            sub @ 1..=8 => {
                let slot = pdo.entries.get_mut(usize::from(sub) - 1)?;
                *slot = Some(u32_value?);
                None
            }
            _ => None,
        }
    }

    /// The identifier the PDO's frames use now, or why there is none.
    fn id_of(&self, key: Key) -> Result<u16, &'static str> {
        match self.pdos.get(&key).and_then(|p| p.cob_id) {
            Some(raw) if raw & 0x8000_0000 != 0 => Err("not valid (COB-ID bit 31 set)"),
            Some(raw) if raw & 0x2000_0000 != 0 => Err("on a 29-bit identifier (not mapped)"),
            Some(raw) => u16::try_from(raw & 0x7FF).map_err(|_| "on no identifier"),
            None => predefined(key).ok_or("on a COB-ID the log has not shown"),
        }
    }

    /// The mapping now `count` entries long.
    fn remap(&mut self, key: Key, count: u8) -> String {
        self.deactivate(key);
        let Some(pdo) = self.pdos.get(&key).copied() else {
            return format!("{}: mapping unknown", name(key));
        };
        if count == 0 {
            return format!("{}: mapping cleared (0 entries)", name(key));
        }
        let n = usize::from(count);
        let entries: Option<Vec<MappingEntry>> = pdo
            .entries
            .get(..n)
            .map(|s| s.iter().map(|e| e.map(MappingEntry::from_u32)).collect())
            .unwrap_or(None);
        let Some(entries) = entries else {
            return format!(
                "{}: {count} entries, not all of them seen in the log; its frames stay raw",
                name(key)
            );
        };
        let mapping = match PdoMapping::new(&entries) {
            Ok(m) => m,
            Err(e) => return format!("{}: mapping not usable ({e})", name(key)),
        };
        let list: Vec<String> = entries.iter().map(ToString::to_string).collect();
        match self.id_of(key) {
            Ok(id) => {
                self.activate(key, id, mapping);
                format!(
                    "{} maps {}; applied to the frames on {id:03X}h that follow",
                    name(key),
                    list.join(", ")
                )
            }
            Err(why) => {
                if let Some(p) = self.pdos.get_mut(&key) {
                    p.active = None;
                }
                format!("{} maps {}; it is {why}", name(key), list.join(", "))
            }
        }
    }

    /// The COB-ID changed: the mapping in force moves with it.
    fn moved(&mut self, key: Key) -> String {
        let active = self.pdos.get(&key).and_then(|p| p.active);
        self.deactivate(key);
        match (self.id_of(key), active) {
            (Ok(id), Some((_, m))) => {
                self.activate(key, id, m);
                format!("{} now on {id:03X}h; its mapping applies there", name(key))
            }
            (Ok(id), None) => format!("{} now on {id:03X}h", name(key)),
            (Err(why), Some((_, m))) => {
                // Kept, to apply again once the PDO is valid.
                if let Some(p) = self.pdos.get_mut(&key) {
                    p.active = Some((0, m));
                }
                format!("{} is {why}", name(key))
            }
            (Err(why), None) => format!("{} is {why}", name(key)),
        }
    }

    fn deactivate(&mut self, key: Key) {
        if let Some((id, _)) = self.pdos.get(&key).and_then(|p| p.active) {
            if self.by_id.get(&id).is_some_and(|(k, ..)| *k == key) {
                self.by_id.remove(&id);
            }
        }
    }

    fn activate(&mut self, key: Key, id: u16, mapping: PdoMapping) {
        if let Some(p) = self.pdos.get_mut(&key) {
            p.active = Some((id, mapping));
        }
        self.by_id.insert(id, (key, mapping, Origin::Log));
    }
}

/// Every variable of an EDS with its name and data type: `(index, sub,
/// name, type)`, the sub-objects of arrays and records named
/// "object name: sub-object name".
fn eds_variables(eds: &Eds) -> Vec<(u16, u8, String, DataType)> {
    let mut out = Vec::new();
    for o in eds.objects.values() {
        if o.subs.is_empty() {
            if let Some(t) = o.entry.data_type {
                out.push((o.index, 0, o.entry.name.clone(), t));
            }
        }
        for (&sub, e) in &o.subs {
            if let Some(t) = e.data_type {
                out.push((o.index, sub, format!("{}: {}", o.entry.name, e.name), t));
            }
        }
    }
    out
}
