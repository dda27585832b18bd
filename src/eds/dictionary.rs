//! From a parsed description, for one node id: an object dictionary the
//! SDO server serves, and the PDOs the description configures.
//!
//! **Lenient in, strict out.** A description is served as far as it can
//! be: every value this crate can encode is in the dictionary, and the
//! ones it cannot (an unknown data type, no data type, a value that does
//! not fit its type) are left out, named with the reason
//! ([`EdsDictionary::unserved`]) and refused on the bus with one abort code
//! ([`EdsDictionary::REFUSAL`]). A program that must serve a file whole
//! refuses it when [`Eds::unserved`] is not empty.

use alloc::vec::Vec;
use core::fmt;

use super::value::{encode_value, eval_int, ValueError};
use super::{DataType, Eds, Entry, ObjectType};
use crate::abort::AbortCode;
use crate::od::index::{
    RPDO_COMMUNICATION, RPDO_COMMUNICATION_LAST, RPDO_MAPPING, TPDO_COMMUNICATION,
    TPDO_COMMUNICATION_LAST,
};
use crate::od::{Access, MemoryDictionary, ObjectDictionary, ObjectInfo};
use crate::pdo::{MappingEntry, MappingError, PdoCobId, PdoDirection, PdoMapping};
use crate::NodeId;

/// The longest download a string or domain object of the built dictionary
/// accepts (or its default's length, if longer).
pub const MAX_VARIABLE_LEN: usize = 1024;

/// A value of the description that the built dictionary does not hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Unserved {
    /// The index.
    pub index: u16,
    /// The sub-index (0 for a VAR).
    pub sub: u8,
    /// The line of its section header (from 1); 0 for a generated entry
    /// (a `CompactSubObj` sub-object).
    pub line: usize,
    /// Why it is left out.
    pub reason: UnservedReason,
}

/// Why a value of the description is left out of its dictionary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum UnservedReason {
    /// `DataType=` names a type this crate has no encoding for: not one of
    /// the CiA 301 basic types (CiA 301, section 7.4.7 "Data type entry
    /// specification") but a DEFTYPE, a DEFSTRUCT, or a manufacturer- or
    /// profile-specific complex type (0040h-025Fh), whose size and layout
    /// the description does not give.
    UnknownDataType(u16),
    /// A VAR or sub-object without `DataType=` (CiA 306, section 4.6
    /// "Object descriptions", makes it mandatory).
    NoDataType,
    /// Its value (`ParameterValue`, else `DefaultValue`) does not encode in
    /// its data type for this node id.
    Value(ValueError),
}

impl fmt::Display for UnservedReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnservedReason::UnknownDataType(t) => {
                write!(f, "data type {t:04X}h has no encoding in this crate")
            }
            UnservedReason::NoDataType => f.write_str("no DataType"),
            UnservedReason::Value(e) => write!(f, "its value does not encode: {e}"),
        }
    }
}

impl fmt::Display for Unserved {
    /// `2020h:00 (line 887): data type 0040h has no encoding in this crate`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04X}h:{:02X}", self.index, self.sub)?;
        if self.line != 0 {
            write!(f, " (line {})", self.line)?;
        }
        write!(f, ": {}", self.reason)
    }
}

/// The dictionary a description gives for one node ([`Eds::dictionary`]):
/// every value it can encode, held in a [`MemoryDictionary`]
/// ([`values`](Self::values)), and the values it cannot
/// ([`unserved`](Self::unserved)), which it refuses.
///
/// **The refusal.** An SDO upload or download of a left-out value is
/// aborted with 06040047h, "general internal incompatibility in the
/// device" (CiA 301, section 7.2.4.3.17 "Protocol SDO abort transfer", the
/// table of SDO abort codes), and not with 06020000h, "object does not
/// exist in the object dictionary". The object does exist: the device's own
/// description lists it, and a master that loaded the same file
/// (python-canopen does, with a warning) expects it there. It is this
/// device that cannot hold its value. 06020000h would tell the master that
/// its description is wrong for the node, and for a left-out sub-object
/// beside served ones a plain dictionary would answer a third code,
/// 06090011h; 06040047h says one thing for one cause. A sub-index the
/// description does not have, of an object with a left-out value, is
/// 06090011h "sub-index does not exist", as for any described object.
///
/// ```
/// use canopen_codec::eds::{parse, EdsDictionary};
/// use canopen_codec::od::ObjectDictionary;
/// use canopen_codec::NodeId;
/// let eds = parse("[2000]\nDataType=0x40\nDefaultValue=0\n\
///                  [2001]\nDataType=6\nAccessType=rw\nDefaultValue=7\n").unwrap();
/// let od = eds.dictionary(NodeId::new(5).unwrap());
/// assert_eq!(od.values().get(0x2001, 0), Some(&[7, 0][..]));
/// assert_eq!(od.unserved()[0].to_string(),
///            "2000h:00 (line 1): data type 0040h has no encoding in this crate");
/// assert_eq!(od.info(0x2000, 0), Err(EdsDictionary::REFUSAL));
/// assert_eq!(u32::from(EdsDictionary::REFUSAL), 0x0604_0047);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EdsDictionary {
    values: MemoryDictionary,
    /// Sorted by index and sub-index.
    unserved: Vec<Unserved>,
}

impl EdsDictionary {
    /// The abort code of an SDO access to a left-out value: 06040047h
    /// (see the type's documentation for why).
    pub const REFUSAL: AbortCode = AbortCode::GeneralInternalIncompatibility;

    /// The values served.
    #[must_use]
    pub fn values(&self) -> &MemoryDictionary {
        &self.values
    }

    /// The values served, for the application to change
    /// ([`MemoryDictionary::set`]).
    pub fn values_mut(&mut self) -> &mut MemoryDictionary {
        &mut self.values
    }

    /// The values served, without the refusals.
    #[must_use]
    pub fn into_values(self) -> MemoryDictionary {
        self.values
    }

    /// The values of the description left out, by index and sub-index,
    /// with the reason.
    #[must_use]
    pub fn unserved(&self) -> &[Unserved] {
        &self.unserved
    }

    /// Why `index`/`sub` is left out, if it is.
    #[must_use]
    pub fn refused(&self, index: u16, sub: u8) -> Option<&Unserved> {
        let at = self
            .unserved
            .binary_search_by_key(&(index, sub), |u| (u.index, u.sub))
            .ok()?;
        self.unserved.get(at)
    }

    /// [`REFUSAL`](Self::REFUSAL) for a left-out value.
    fn gate(&self, index: u16, sub: u8) -> Result<(), AbortCode> {
        match self.refused(index, sub) {
            Some(_) => Err(Self::REFUSAL),
            None => Ok(()),
        }
    }

    /// What the served values answered, except that an object with
    /// left-out values exists: a sub-index it does not have is 06090011h.
    fn existing<T>(&self, index: u16, answer: Result<T, AbortCode>) -> Result<T, AbortCode> {
        match answer {
            Err(AbortCode::ObjectDoesNotExist)
                if self.unserved.iter().any(|u| u.index == index) =>
            {
                Err(AbortCode::SubIndexDoesNotExist)
            }
            other => other,
        }
    }
}

impl ObjectDictionary for EdsDictionary {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        self.gate(index, sub)?;
        self.existing(index, self.values.info(index, sub))
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        self.gate(index, sub)?;
        let answer = self.values.read(index, sub, offset, buf);
        self.existing(index, answer)
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        self.gate(index, sub)?;
        let answer = self.values.write(index, sub, offset, data);
        self.existing(index, answer)
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        self.gate(index, sub)?;
        let answer = self.values.finish_write(index, sub, len);
        self.existing(index, answer)
    }

    fn abort_write(&mut self, index: u16, sub: u8) {
        self.values.abort_write(index, sub);
    }
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

/// The data type of a value entry: `Ok(None)` for an entry that is not a
/// value (a DEFTYPE or DEFSTRUCT definition), or why it has none this
/// crate encodes.
pub(super) fn data_type_of(e: &Entry) -> Result<Option<DataType>, UnservedReason> {
    if matches!(e.object_type, ObjectType::DefType | ObjectType::DefStruct) {
        return Ok(None);
    }
    match (e.data_type, e.object_type) {
        (Some(DataType::Other(raw)), _) => Err(UnservedReason::UnknownDataType(raw)),
        (Some(t), _) => Ok(Some(t)),
        (None, ObjectType::Domain) => Ok(Some(DataType::Domain)),
        (None, _) => Err(UnservedReason::NoDataType),
    }
}

/// What the dictionary holds for one entry: `Ok(None)` for an entry that
/// is not a value (a DEFTYPE or DEFSTRUCT definition), else its data type
/// and its bytes for `node`, or why it is left out.
fn value_of(e: &Entry, node: u8) -> Result<Option<(DataType, Vec<u8>)>, UnservedReason> {
    let Some(data_type) = data_type_of(e)? else {
        return Ok(None);
    };
    let value = encode_value(data_type, e.value().unwrap_or(""), Some(node))
        .map_err(UnservedReason::Value)?;
    Ok(Some((data_type, value)))
}

impl Eds {
    /// Every entry that describes a value, in index and sub-index order: a
    /// VAR's own section at sub-index 0, each sub-object of the others.
    pub(super) fn value_entries(&self) -> impl Iterator<Item = (u16, u8, &Entry)> + '_ {
        self.objects.values().flat_map(|o| {
            let own = o.subs.is_empty().then_some((o.index, 0, &o.entry));
            let subs = o.subs.iter().map(move |(&sub, e)| (o.index, sub, e));
            own.into_iter().chain(subs)
        })
    }

    /// The dictionary of the description for `node`: each VAR and DOMAIN,
    /// and each sub-object of an ARRAY or RECORD, with its access
    /// (`rwr`/`rww` as `rw`), its size from the data type, its
    /// PDO-mappable flag and its `ParameterValue` (DCF) or `DefaultValue`
    /// (see [`encode_value`]). DEFTYPE and DEFSTRUCT definitions are not
    /// values. A value this crate cannot encode (see [`UnservedReason`]) is
    /// left out, named in [`EdsDictionary::unserved`] and refused on the
    /// bus with [`EdsDictionary::REFUSAL`]; every other value is served.
    #[must_use]
    pub fn dictionary(&self, node: NodeId) -> EdsDictionary {
        let mut od = EdsDictionary::default();
        for (index, sub, e) in self.value_entries() {
            match value_of(e, node.raw()) {
                Ok(None) => {}
                Ok(Some((data_type, value))) => {
                    let access = e.access.map_or(Access::ReadOnly, |a| a.access());
                    if data_type.fixed_size().is_some() {
                        od.values.insert(index, sub, access, &value);
                    } else {
                        let max = value.len().max(MAX_VARIABLE_LEN);
                        od.values.insert_variable(index, sub, access, &value, max);
                    }
                    od.values.set_mappable(index, sub, e.pdo_mapping);
                }
                Err(reason) => od.unserved.push(Unserved {
                    index,
                    sub,
                    line: e.line,
                    reason,
                }),
            }
        }
        od.unserved.sort_unstable_by_key(|u| (u.index, u.sub));
        od
    }

    /// The values of the description that [`dictionary`](Self::dictionary)
    /// leaves out for `node`, in index and sub-index order, each with the
    /// line of its section and the reason (the same list as
    /// [`EdsDictionary::unserved`], without building the dictionary). A
    /// program that must serve a file whole refuses it when this is not
    /// empty, naming them.
    #[must_use]
    pub fn unserved(&self, node: NodeId) -> Vec<Unserved> {
        self.value_entries()
            .filter_map(|(index, sub, e)| {
                let reason = value_of(e, node.raw()).err()?;
                Some(Unserved {
                    index,
                    sub,
                    line: e.line,
                    reason,
                })
            })
            .collect()
    }

    /// Every PDO whose communication parameter (1400h-15FFh receive,
    /// 1800h-19FFh transmit) the description has, with its COB-ID and
    /// transmission type for `node` and the mapping entries of the
    /// matching 1600h/1A00h object.
    #[must_use]
    pub fn pdos(&self, node: NodeId) -> Vec<PdoDescription> {
        let node = node.raw();
        let ranges = [
            (
                PdoDirection::Receive,
                RPDO_COMMUNICATION..=RPDO_COMMUNICATION_LAST,
            ),
            (
                PdoDirection::Transmit,
                TPDO_COMMUNICATION..=TPDO_COMMUNICATION_LAST,
            ),
        ];
        let mut out = Vec::new();
        for (direction, range) in ranges {
            let base = *range.start();
            for (&index, _) in self.objects.range(range) {
                let number = index.saturating_sub(base);
                let mapping_index = index.saturating_add(RPDO_MAPPING - RPDO_COMMUNICATION);
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

#[cfg(test)]
mod tests {
    use alloc::string::ToString;

    use super::*;
    use crate::eds::parse;

    fn node(raw: u8) -> NodeId {
        NodeId::new(raw).unwrap()
    }

    /// 2000h of a complex type, 2001h a record whose sub 1 has no data
    /// type, 2002h a plain VAR, 2003h a value too big for its type.
    const MIXED: &str = "[2000]\nParameterName=Complex\nDataType=0x40\nDefaultValue=0\n\
                         [2001]\nObjectType=0x9\nSubNumber=2\n\
                         [2001sub0]\nDataType=5\nDefaultValue=1\n\
                         [2001sub1]\nAccessType=rw\n\
                         [2002]\nDataType=7\nAccessType=rw\nDefaultValue=1\n\
                         [2003]\nDataType=5\nDefaultValue=0x100\n";

    #[test]
    fn what_it_cannot_encode_is_named_with_line_and_reason() {
        let eds = parse(MIXED).unwrap();
        let od = eds.dictionary(node(5));
        let named: Vec<_> = od
            .unserved()
            .iter()
            .map(|u| (u.index, u.sub, u.line, u.reason))
            .collect();
        assert_eq!(
            named,
            [
                (0x2000, 0, 1, UnservedReason::UnknownDataType(0x40)),
                (0x2001, 1, 11, UnservedReason::NoDataType),
                (0x2003, 0, 17, UnservedReason::Value(ValueError::OutOfRange)),
            ]
        );
        assert_eq!(eds.unserved(node(5)), od.unserved());
        let said: Vec<_> = od.unserved().iter().map(ToString::to_string).collect();
        assert_eq!(
            said,
            [
                "2000h:00 (line 1): data type 0040h has no encoding in this crate",
                "2001h:01 (line 11): no DataType",
                "2003h:00 (line 17): its value does not encode: value out of range for the data type",
            ]
        );
        // Everything else is served.
        assert_eq!(od.values().len(), 2);
        assert_eq!(od.values().get(0x2001, 0), Some(&[1][..]));
        assert_eq!(od.values().get(0x2002, 0), Some(&[1, 0, 0, 0][..]));
        assert!(parse("[2002]\nDataType=7\nDefaultValue=1\n")
            .unwrap()
            .unserved(node(5))
            .is_empty());
    }

    #[test]
    fn a_left_out_value_is_refused_with_one_code() {
        let mut od = parse(MIXED).unwrap().dictionary(node(5));
        let mut buf = [0u8; 4];
        for (index, sub) in [(0x2000, 0), (0x2001, 1), (0x2003, 0)] {
            assert!(od.refused(index, sub).is_some());
            assert_eq!(od.info(index, sub), Err(EdsDictionary::REFUSAL));
            assert_eq!(
                od.read(index, sub, 0, &mut buf),
                Err(EdsDictionary::REFUSAL)
            );
            assert_eq!(od.write(index, sub, 0, &[1]), Err(EdsDictionary::REFUSAL));
            assert_eq!(od.finish_write(index, sub, 1), Err(EdsDictionary::REFUSAL));
        }
        assert_eq!(u32::from(EdsDictionary::REFUSAL), 0x0604_0047);
        // The objects exist: a sub-index they do not have is 06090011h,
        // an index the description does not have 06020000h.
        assert_eq!(od.info(0x2000, 1), Err(AbortCode::SubIndexDoesNotExist));
        assert_eq!(od.info(0x2001, 2), Err(AbortCode::SubIndexDoesNotExist));
        assert_eq!(
            od.read(0x2003, 1, 0, &mut buf),
            Err(AbortCode::SubIndexDoesNotExist)
        );
        assert_eq!(od.info(0x3000, 0), Err(AbortCode::ObjectDoesNotExist));
        // Served values beside them read and write as usual.
        assert_eq!(od.read(0x2001, 0, 0, &mut buf), Ok(1));
        assert_eq!(od.write(0x2002, 0, 0, &[9, 0, 0, 0]), Ok(()));
        assert_eq!(od.finish_write(0x2002, 0, 4), Ok(()));
        assert_eq!(od.values().get(0x2002, 0), Some(&[9, 0, 0, 0][..]));
        assert!(od.refused(0x2002, 0).is_none());
        assert_eq!(od.clone().into_values(), *od.values());
        assert!(od.values_mut().set(0x2002, 0, &[1, 0, 0, 0]));
    }

    #[test]
    fn a_node_id_sum_that_overflows_leaves_out_that_node_only() {
        let eds = parse(
            "[1200]\nObjectType=9\n[1200sub0]\nDataType=5\nDefaultValue=1\n\
                         [1200sub1]\nDataType=5\nDefaultValue=$NODEID+0x81\n",
        )
        .unwrap();
        assert!(eds.unserved(node(126)).is_empty());
        assert_eq!(
            eds.dictionary(node(126)).values().get(0x1200, 1),
            Some(&[0xFF][..])
        );
        let od = eds.dictionary(node(127));
        assert_eq!(
            od.unserved(),
            [Unserved {
                index: 0x1200,
                sub: 1,
                line: 6,
                reason: UnservedReason::Value(ValueError::OutOfRange)
            }]
        );
        assert_eq!(od.values().get(0x1200, 0), Some(&[1][..]));
    }

    #[test]
    fn definitions_are_not_values() {
        let eds = parse(
            "[0005]\nObjectType=0x5\nDataType=7\n\
                         [0040]\nObjectType=0x6\nSubNumber=1\n\
                         [0040sub0]\nObjectType=0x5\nDataType=5\n",
        )
        .unwrap();
        let od = eds.dictionary(node(1));
        assert!(od.values().is_empty() && od.unserved().is_empty());
    }
}
