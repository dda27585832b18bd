//! A description of a dictionary we serve ourselves: an [`Eds`] model
//! built from any [`ObjectDictionary`], ready for [`write`](super::write).

use alloc::collections::BTreeMap;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use alloc::{format, vec};

use super::{AccessType, DataType, Eds, Entry, Object, ObjectType};
use crate::od::{Access, ObjectDictionary, ObjectInfo};

/// What the caller says about one sub-object found in the dictionary: its
/// `ParameterName` and data type (the dictionary itself knows only sizes).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Described {
    /// `ParameterName`.
    pub name: String,
    /// `DataType`.
    pub data_type: DataType,
}

/// The longest current value written as a `DefaultValue`.
const MAX_DEFAULT_LEN: usize = 4096;

const fn access_type(a: Access) -> AccessType {
    match a {
        Access::ReadOnly => AccessType::ReadOnly,
        Access::WriteOnly => AccessType::WriteOnly,
        Access::ReadWrite => AccessType::ReadWrite,
        Access::Const => AccessType::Const,
    }
}

/// The text [`encode_value`](super::encode_value) reads back to `bytes`.
fn value_text(t: DataType, bytes: &[u8]) -> Option<String> {
    match t {
        DataType::VisibleString => {
            let s = core::str::from_utf8(bytes).ok()?;
            // Only what a line of EDS can hold unchanged.
            let plain = s.trim() == s && !s.contains(['\n', '\r', ';']);
            return plain.then(|| s.to_string());
        }
        DataType::OctetString | DataType::Domain => {
            return Some(bytes.iter().map(|b| format!("{b:02X}")).collect());
        }
        _ => {}
    }
    let size = t.fixed_size()?;
    if bytes.len() != size {
        return None;
    }
    let mut le = [0u8; 8];
    le.get_mut(..size)?.copy_from_slice(bytes);
    let raw = u64::from_le_bytes(le);
    Some(match t {
        DataType::Real32 => format!("{:?}", f32::from_bits(u32::try_from(raw).ok()?)),
        DataType::Real64 => format!("{:?}", f64::from_bits(raw)),
        _ if t.is_signed() => {
            let bits = u32::try_from(size.saturating_mul(8)).ok()?;
            format!("{}", crate::pdo::sign_extend(raw, bits))
        }
        _ => format!("{raw}"),
    })
}

impl Eds {
    /// Describes the objects `indexes` of `od`: each sub-object that
    /// answers [`ObjectDictionary::info`] (an object with sub-objects 1 and
    /// up becomes a RECORD, one with only sub-index 0 a VAR), with its
    /// access, PDO-mappable flag and current value as `DefaultValue`, and
    /// the name and data type `describe` gives (entries it returns `None`
    /// for are left out). Objects go to the CiA 306 object list their index
    /// belongs to: 1000h, 1001h and 1018h mandatory, 1000h-1FFFh and
    /// 6000h-FFFFh optional, 2000h-5FFFh manufacturer (CiA 306, section
    /// 4.5 "Object lists").
    pub fn from_dictionary<D: ObjectDictionary + ?Sized>(
        od: &mut D,
        indexes: &[u16],
        mut describe: impl FnMut(u16, u8, &ObjectInfo) -> Option<Described>,
    ) -> Eds {
        let mut eds = Eds::default();
        for &index in indexes {
            let mut subs = BTreeMap::new();
            for sub in 0..=u8::MAX {
                let Ok(info) = od.info(index, sub) else {
                    continue;
                };
                let Some(d) = describe(index, sub, &info) else {
                    continue;
                };
                // Values longer than any EDS line should hold are left out.
                let mut value = vec![0u8; info.len.min(MAX_DEFAULT_LEN)];
                let default = match od.read(index, sub, 0, &mut value) {
                    Ok(n) if info.access.is_readable() && info.len <= MAX_DEFAULT_LEN => {
                        value.truncate(n);
                        value_text(d.data_type, &value)
                    }
                    _ => None,
                };
                let entry = Entry {
                    name: d.name,
                    data_type: Some(d.data_type),
                    access: Some(access_type(info.access)),
                    pdo_mapping: info.pdo_mappable,
                    default_value: default,
                    ..Entry::default()
                };
                subs.insert(sub, entry);
            }
            let object = match subs.len() {
                0 => continue,
                1 if subs.contains_key(&0) => Object {
                    index,
                    entry: subs.remove(&0).unwrap_or_default(),
                    subs: BTreeMap::new(),
                },
                n => Object {
                    index,
                    entry: Entry {
                        name: subs.get(&0).map_or_else(String::new, |e| e.name.clone()),
                        object_type: ObjectType::Record,
                        sub_number: u16::try_from(n).ok(),
                        ..Entry::default()
                    },
                    subs,
                },
            };
            let list: &mut Vec<u16> = match index {
                0x1000 | 0x1001 | 0x1018 => &mut eds.mandatory,
                0x2000..=0x5FFF => &mut eds.manufacturer,
                _ => &mut eds.optional,
            };
            list.push(index);
            eds.objects.insert(index, object);
        }
        eds
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::od::{MemoryDictionary, ObjectDictionary};
    use crate::NodeId;

    #[test]
    fn a_dictionary_described_written_and_read_back() {
        let mut od = MemoryDictionary::new();
        od.insert(0x1000, 0, Access::Const, &0x0001_0192u32.to_le_bytes());
        od.insert_variable(0x1008, 0, Access::Const, b"virtual charger", 32);
        od.insert(0x1018, 0, Access::Const, &[1]);
        od.insert(0x1018, 1, Access::ReadOnly, &0x110u32.to_le_bytes());
        od.insert(0x2100, 0, Access::WriteOnly, &[0; 2]);
        od.insert(0x6010, 0, Access::ReadOnly, &(-40i16).to_le_bytes());
        od.set_mappable(0x6010, 0, true);
        od.insert(0x2200, 0, Access::ReadWrite, &1.5f32.to_le_bytes());
        let types = |index: u16, sub: u8| match (index, sub) {
            (0x1000, _) | (0x1018, 1) => DataType::Unsigned32,
            (0x1008, _) => DataType::VisibleString,
            (0x1018, 0) => DataType::Unsigned8,
            (0x2100, _) => DataType::Unsigned16,
            (0x2200, _) => DataType::Real32,
            _ => DataType::Integer16,
        };
        let indexes = [0x1000, 0x1008, 0x1018, 0x2100, 0x2200, 0x6010, 0x7000];
        let eds = Eds::from_dictionary(&mut od, &indexes, |i, s, _| {
            Some(Described {
                name: format!("object {i:04X}h/{s}"),
                data_type: types(i, s),
            })
        });
        assert_eq!(eds.mandatory, [0x1000, 0x1018]);
        assert_eq!(eds.optional, [0x1008, 0x6010]);
        assert_eq!(eds.manufacturer, [0x2100, 0x2200]);
        assert_eq!(eds.objects[&0x1018].entry.object_type, ObjectType::Record);
        assert_eq!(
            eds.objects[&0x6010].entry.default_value.as_deref(),
            Some("-40")
        );
        assert_eq!(eds.objects[&0x2100].entry.default_value, None);
        let text = super::super::write(&eds);
        let back = super::super::parse(&text).unwrap();
        let node = NodeId::MIN;
        let mut od2 = back.dictionary(node).unwrap();
        for (index, sub) in [
            (0x1000, 0),
            (0x1008, 0),
            (0x1018, 0),
            (0x1018, 1),
            (0x6010, 0),
            (0x2200, 0),
        ] {
            let (a, b) = (od.info(index, sub).unwrap(), od2.info(index, sub).unwrap());
            assert_eq!(
                (a.access, a.len, a.pdo_mappable),
                (b.access, b.len, b.pdo_mappable)
            );
            let mut x = [0u8; 32];
            let mut y = [0u8; 32];
            assert_eq!(
                od.read(index, sub, 0, &mut x),
                od2.read(index, sub, 0, &mut y)
            );
            assert_eq!(x, y, "{index:04X}h/{sub}");
        }
        assert_eq!(od2.info(0x2100, 0).unwrap().access, Access::WriteOnly);
    }

    #[test]
    fn value_texts_read_back() {
        use super::super::encode_value;
        let cases: [(DataType, &[u8]); 6] = [
            (DataType::Integer24, &[0xFF, 0xFF, 0xFF]),
            (DataType::Unsigned64, &[0xFF; 8]),
            (DataType::Real64, &[0, 0, 0, 0, 0, 0, 0xF8, 0x7F]),
            (DataType::Domain, &[1, 0xAB]),
            (DataType::VisibleString, b"IC650"),
            (DataType::Boolean, &[1]),
        ];
        for (t, bytes) in cases {
            let text = value_text(t, bytes).unwrap();
            assert_eq!(encode_value(t, &text, None).unwrap(), bytes, "{t:?} {text}");
        }
        assert_eq!(value_text(DataType::VisibleString, b" padded"), None);
        assert_eq!(value_text(DataType::Unsigned16, &[1]), None);
    }
}
