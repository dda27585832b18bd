//! From a parsed description, for one node id: an object dictionary the
//! SDO server serves, and the PDOs the description configures.

use alloc::vec::Vec;

use super::value::{encode_value, eval_int, ValueError};
use super::{DataType, Eds, Entry, ObjectType};
use crate::od::{Access, MemoryDictionary};
use crate::pdo::{MappingEntry, MappingError, PdoCobId, PdoDirection, PdoMapping};
use crate::NodeId;

/// The longest download a string or domain object of the built dictionary
/// accepts (or its default's length, if longer).
pub const MAX_VARIABLE_LEN: usize = 1024;

/// Why a description could not be built into a dictionary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum DictionaryError {
    /// A value (`ParameterValue`, else `DefaultValue`) does not encode in
    /// the entry's data type.
    #[error("{index:04X}h sub {sub}: {error}")]
    Value {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// Why.
        error: ValueError,
    },
}

/// What the description says about one PDO (CiA 301, section 7.5.2.35 to
/// 7.5.2.38, the PDO communication and mapping parameters 1400h-1BFFh).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PdoDescription {
    /// Receive (1400h/1600h) or transmit (1800h/1A00h).
    pub direction: PdoDirection,
    /// Zero-based number: the communication index minus 1400h or 1800h.
    pub number: u16,
    /// Sub-index 1 of the communication parameter, with `$NODEID`
    /// resolved (`None` if absent or not a number).
    pub cob_id: Option<PdoCobId>,
    /// Sub-index 2, the transmission type.
    pub transmission_type: Option<u8>,
    /// The mapping parameter's entries 1..=sub 0 as written.
    pub entries: Vec<MappingEntry>,
}

impl PdoDescription {
    /// The mapping as a checked [`PdoMapping`].
    pub fn mapping(&self) -> Result<PdoMapping, MappingError> {
        PdoMapping::new(&self.entries)
    }
}

/// The value of `entry` for `node` as an integer.
fn int_of(entry: Option<&Entry>, node: u8) -> Option<i128> {
    eval_int(entry?.value()?, Some(node)).ok()
}

/// What the built dictionary holds for one entry: `None` for entries that
/// are not values (DEFTYPE and DEFSTRUCT definitions, ARRAY/RECORD heads).
fn add_entry(
    od: &mut MemoryDictionary,
    (index, sub): (u16, u8),
    e: &Entry,
    node: u8,
) -> Result<(), DictionaryError> {
    if matches!(e.object_type, ObjectType::DefType | ObjectType::DefStruct) {
        return Ok(());
    }
    let data_type = match (e.data_type, e.object_type) {
        // A DEFTYPE/DEFSTRUCT or manufacturer type has no known size.
        (Some(DataType::Other(_)), _) => return Ok(()),
        (Some(t), _) => t,
        (None, ObjectType::Domain) => DataType::Domain,
        (None, _) => return Ok(()),
    };
    let access = e.access.map_or(Access::ReadOnly, |a| a.access());
    let text = e.value().unwrap_or("");
    let value = encode_value(data_type, text, Some(node))
        .map_err(|error| DictionaryError::Value { index, sub, error })?;
    if data_type.fixed_size().is_some() {
        od.insert(index, sub, access, &value);
    } else {
        let max = value.len().max(MAX_VARIABLE_LEN);
        od.insert_variable(index, sub, access, &value, max);
    }
    od.set_mappable(index, sub, e.pdo_mapping);
    Ok(())
}

impl Eds {
    /// An in-memory dictionary holding every value of the description for
    /// `node`: each VAR and DOMAIN, and each sub-object of an ARRAY or
    /// RECORD, with its access (`rwr`/`rww` as `rw`), its size from the
    /// data type, its PDO-mappable flag and its `ParameterValue` (DCF) or
    /// `DefaultValue` (see [`encode_value`]). DEFTYPE and DEFSTRUCT
    /// definitions, entries without a data type and entries of a data type
    /// this crate has no encoding for ([`DataType::Other`]) are left out:
    /// [`unserved`](Self::unserved) names the last two, so that a program
    /// serving the file can refuse it rather than serve part of it.
    pub fn dictionary(&self, node: NodeId) -> Result<MemoryDictionary, DictionaryError> {
        let mut od = MemoryDictionary::new();
        for o in self.objects.values() {
            if o.subs.is_empty() {
                add_entry(&mut od, (o.index, 0), &o.entry, node.raw())?;
            }
            for (&sub, e) in &o.subs {
                add_entry(&mut od, (o.index, sub), e, node.raw())?;
            }
        }
        Ok(od)
    }

    /// The values of the description that [`dictionary`](Self::dictionary)
    /// cannot serve, by index and sub-index: entries of a data type this
    /// crate has no encoding for ([`DataType::Other`]) and VAR entries
    /// without a data type. A program that must serve the file whole
    /// refuses it when this is not empty, naming them.
    #[must_use]
    pub fn unserved(&self) -> Vec<(u16, u8)> {
        let mut out = Vec::new();
        let mut check = |index: u16, sub: u8, e: &Entry| {
            if matches!(e.object_type, ObjectType::DefType | ObjectType::DefStruct) {
                return;
            }
            let served = match (e.data_type, e.object_type) {
                (Some(DataType::Other(_)), _) => false,
                (Some(_), _) | (None, ObjectType::Domain) => true,
                (None, _) => false,
            };
            if !served {
                out.push((index, sub));
            }
        };
        for o in self.objects.values() {
            if o.subs.is_empty() {
                check(o.index, 0, &o.entry);
            }
            for (&sub, e) in &o.subs {
                check(o.index, sub, e);
            }
        }
        out
    }

    /// Every PDO whose communication parameter (1400h-15FFh receive,
    /// 1800h-19FFh transmit) the description has, with its COB-ID and
    /// transmission type for `node` and the mapping entries of the
    /// matching 1600h/1A00h object.
    #[must_use]
    pub fn pdos(&self, node: NodeId) -> Vec<PdoDescription> {
        let node = node.raw();
        let ranges = [
            (PdoDirection::Receive, 0x1400u16..=0x15FF),
            (PdoDirection::Transmit, 0x1800..=0x19FF),
        ];
        let mut out = Vec::new();
        for (direction, range) in ranges {
            let base = *range.start();
            for (&index, _) in self.objects.range(range) {
                let number = index.saturating_sub(base);
                let mapping_index = index.saturating_add(0x200);
                let count = int_of(self.entry(mapping_index, 0), node).unwrap_or(0);
                let entries = (1..=count.clamp(0, 0x40))
                    .filter_map(|sub| {
                        let sub = u8::try_from(sub).ok()?;
                        let raw = int_of(self.entry(mapping_index, sub), node)?;
                        Some(MappingEntry::from_u32(u32::try_from(raw).ok()?))
                    })
                    .collect();
                out.push(PdoDescription {
                    direction,
                    number,
                    cob_id: int_of(self.entry(index, 1), node)
                        .and_then(|v| u32::try_from(v).ok())
                        .map(PdoCobId::from_u32),
                    transmission_type: int_of(self.entry(index, 2), node)
                        .and_then(|v| u8::try_from(v).ok()),
                    entries,
                });
            }
        }
        out
    }
}
