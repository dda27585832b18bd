//! A description of a dictionary we serve ourselves: an [`Eds`] model
//! built from any [`ObjectDictionary`], ready for [`write`](super::write).

use alloc::collections::BTreeMap;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use alloc::{format, vec};

use super::{AccessType, DataType, Eds, Entry, Keys, Object, ObjectType};
use crate::od::comm::COMM_OBJECTS;
use crate::od::index::{
    DEVICE_TYPE, ERROR_REGISTER, IDENTITY, MANUFACTURER_DEVICE_NAME, RPDO_COMMUNICATION,
    RPDO_COMMUNICATION_LAST, TPDO_COMMUNICATION, TPDO_COMMUNICATION_LAST,
};
use crate::od::{Access, Address, ObjectDictionary, ObjectInfo, ObjectRow};

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
    /// Describes a device profile's node (see [`describe`](Self::describe)):
    /// the communication objects named and typed by CiA 301
    /// ([`COMM_OBJECTS`]), the application objects by the rows of its
    /// profile's table `profile` (CiA 418 v1.0.1 for a battery module, the
    /// Delta-Q table for the IC Series charger).
    pub fn describe_profile<D: ObjectDictionary + ?Sized>(
        od: &mut D,
        profile: &[ObjectRow],
        header: &DeviceHeader<'_>,
    ) -> Eds {
        Self::describe(
            od,
            &[ObjectNames::Rows(COMM_OBJECTS), ObjectNames::Rows(profile)],
            header,
        )
    }

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
                DEVICE_TYPE | ERROR_REGISTER | IDENTITY => &mut eds.mandatory,
                0x2000..=0x5FFF => &mut eds.manufacturer,
                _ => &mut eds.optional,
            };
            list.push(index);
            eds.objects.insert(index, object);
        }
        eds
    }
}

/// One line of a description table: an object (or a run of objects, such
/// as the PDO parameters 1400h-15FFh) with its `ParameterName`, its
/// `ObjectType` and the name and data type of each sub-object, as CiA 306
/// ("Electronic data sheet specification for CANopen", section 4.6 "Object
/// descriptions") writes them. [`Eds::describe`] turns a dictionary and
/// such tables into an [`Eds`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjectDescription {
    /// The first index described.
    pub first: u16,
    /// The last index described (`first` for a single object).
    pub last: u16,
    /// `ParameterName`; for a run of objects, `" <n>"` is appended, `n`
    /// counting from 1 at `first`.
    pub name: &'static str,
    /// VAR, ARRAY or RECORD.
    pub object_type: ObjectType,
    /// The data type of a VAR (unused for an ARRAY or RECORD).
    pub data_type: DataType,
    /// The sub-objects of an ARRAY or RECORD (empty for a VAR).
    pub subs: &'static [SubDescription],
}

/// Names and data type of a run of sub-indexes of an [`ObjectDescription`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SubDescription {
    /// The first sub-index.
    pub first: u8,
    /// The last sub-index (`first` for a single sub-object).
    pub last: u8,
    /// `ParameterName`; for a run, `" <sub>"` is appended.
    pub name: &'static str,
    /// `DataType`.
    pub data_type: DataType,
}

impl ObjectDescription {
    /// A VAR at `index`.
    #[must_use]
    pub const fn var(index: u16, name: &'static str, data_type: DataType) -> Self {
        ObjectDescription {
            first: index,
            last: index,
            name,
            object_type: ObjectType::Var,
            data_type,
            subs: &[],
        }
    }

    /// An ARRAY or RECORD at `first..=last` with sub-objects `subs`.
    #[must_use]
    pub const fn with_subs(
        first: u16,
        last: u16,
        name: &'static str,
        object_type: ObjectType,
        subs: &'static [SubDescription],
    ) -> Self {
        ObjectDescription {
            first,
            last,
            name,
            object_type,
            data_type: DataType::Domain,
            subs,
        }
    }

    /// The `ParameterName` of object `index` (which this line covers).
    fn object_name(&self, index: u16) -> String {
        if self.first == self.last {
            self.name.to_string()
        } else {
            let n = u32::from(index.saturating_sub(self.first)).saturating_add(1);
            format!("{} {n}", self.name)
        }
    }

    /// The name and data type of `sub` of `index`, if this line has it.
    fn sub(&self, index: u16, sub: u8) -> Option<Described> {
        if self.subs.is_empty() {
            return (sub == 0).then(|| Described {
                name: self.object_name(index),
                data_type: self.data_type,
            });
        }
        let d = self
            .subs
            .iter()
            .find(|d| (d.first..=d.last).contains(&sub))?;
        let name = if d.first == d.last {
            d.name.to_string()
        } else {
            format!("{} {sub}", d.name)
        };
        Some(Described {
            name,
            data_type: d.data_type,
        })
    }
}

/// What `[FileInfo]` and `[DeviceInfo]` say about a device that
/// [`Eds::describe`] describes, besides what its dictionary holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeviceHeader<'a> {
    /// `FileName` (CiA 306, section 4.2 "File information").
    pub file_name: &'a str,
    /// `Description`.
    pub description: &'a str,
    /// `VendorName` (CiA 306, section 4.3 "General device information"),
    /// if known: the vendor-ID of 1018h is written as `VendorNumber`.
    pub vendor_name: Option<&'a str>,
}

/// A table [`Eds::describe`] reads names and types from: CiA 306 object
/// descriptions, or the rows of an object table (such as the CiA 301
/// communication objects, [`crate::od::comm::COMM_OBJECTS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObjectNames<'t> {
    /// Object descriptions, one line per object or run of objects.
    Descriptions(&'t [ObjectDescription]),
    /// Object rows: an object's `ParameterName` and `ObjectType` are
    /// those of its sub-index 0 row ([`ObjectRow::compound`], else the
    /// row's own name and VAR), a sub-object's those of its row; a run of
    /// objects appends `" <n>"` to the object name (`n` from 1), a run of
    /// sub-indexes `" <sub>"` to the sub-object's.
    Rows(&'t [ObjectRow]),
}

impl ObjectNames<'_> {
    /// Every index the table has an object at (a run counted whole).
    fn indexes(&self) -> Vec<u16> {
        let runs: Vec<(u16, u16)> = match self {
            ObjectNames::Descriptions(d) => d.iter().map(|d| (d.first, d.last)).collect(),
            ObjectNames::Rows(rows) => rows
                .iter()
                .filter(|r| r.address.sub == 0)
                .map(|r| (r.address.index, r.last_index))
                .collect(),
        };
        runs.into_iter()
            .flat_map(|(first, last)| first..=last)
            .collect()
    }

    /// The `ParameterName` and `ObjectType` of object `index`, if the table
    /// has it.
    fn object(&self, index: u16) -> Option<(String, ObjectType)> {
        match self {
            ObjectNames::Descriptions(_) => {
                let d = self.description(index)?;
                Some((d.object_name(index), d.object_type))
            }
            ObjectNames::Rows(rows) => {
                let row = ObjectRow::find(rows, Address::index(index)).ok()?;
                let (name, object_type) = row
                    .compound
                    .map_or((row.name, ObjectType::Var), |c| (c.name, c.object_type));
                Some((
                    run_name(name, index, row.address.index, row.last_index),
                    object_type,
                ))
            }
        }
    }

    /// The name and data type of `sub` of `index`, if the table has it.
    fn sub(&self, index: u16, sub: u8) -> Option<Described> {
        match self {
            ObjectNames::Descriptions(_) => self.description(index)?.sub(index, sub),
            ObjectNames::Rows(rows) => {
                let row = ObjectRow::find(rows, Address::new(index, sub)).ok()?;
                let name = if row.compound.is_none() && row.address.sub == 0 {
                    // A VAR: named as its object.
                    run_name(row.name, index, row.address.index, row.last_index)
                } else if row.last_sub > row.address.sub {
                    format!("{} {sub}", row.name)
                } else {
                    row.name.to_string()
                };
                Some(Described {
                    name,
                    data_type: row.data_type,
                })
            }
        }
    }

    /// The description line that covers `index`.
    fn description(&self, index: u16) -> Option<&ObjectDescription> {
        match self {
            ObjectNames::Descriptions(d) => d.iter().find(|d| (d.first..=d.last).contains(&index)),
            ObjectNames::Rows(_) => None,
        }
    }
}

/// `name`, or for object `at` of the run `first..=last` `"name <n>"` (`n`
/// from 1 at `first`).
fn run_name(name: &str, at: u16, first: u16, last: u16) -> String {
    if first == last {
        name.to_string()
    } else {
        let n = u32::from(at.saturating_sub(first)).saturating_add(1);
        format!("{name} {n}")
    }
}

/// The first of `tables` that has object `index`.
fn table_of<'a, 't>(tables: &'a [ObjectNames<'t>], index: u16) -> Option<&'a ObjectNames<'t>> {
    tables.iter().find(|t| t.object(index).is_some())
}

/// A text fit for an EDS line (no comment, no line break, not padded).
fn plain(s: &str) -> Option<&str> {
    (s.trim() == s && !s.contains(['\n', '\r', ';', '\0'])).then_some(s)
}

/// The 32-bit value at `index`/`sub` of `od`, if readable.
fn read_u32<D: ObjectDictionary + ?Sized>(od: &mut D, index: u16, sub: u8) -> Option<u32> {
    let mut b = [0u8; 4];
    match od.read(index, sub, 0, &mut b) {
        Ok(4) => Some(u32::from_le_bytes(b)),
        _ => None,
    }
}

impl Eds {
    /// Describes every object of `od` (one that answers sub-index 0) that a
    /// line of `tables` covers (see
    /// [`from_dictionary`](Self::from_dictionary): values, access and
    /// PDO-mappable flags come from the dictionary, names, data types and
    /// object types from the tables; sub-objects the tables do not name
    /// are left out), with the `[FileInfo]` (CiA 306, section 4.2 "File
    /// information") and `[DeviceInfo]` (section 4.3 "General device
    /// information") of `header`: `ProductName` from 1008h, `VendorNumber`,
    /// `ProductNumber` and `RevisionNumber` from 1018h sub 1-3,
    /// `NrOfRXPDO`/`NrOfTXPDO` from the PDO communication parameters
    /// present, every bit rate (a sans-IO device runs at whatever the bus
    /// runs at), no LSS, simple boot-up slave.
    pub fn describe<D: ObjectDictionary + ?Sized>(
        od: &mut D,
        tables: &[ObjectNames<'_>],
        header: &DeviceHeader<'_>,
    ) -> Eds {
        let mut indexes = Vec::new();
        for index in tables.iter().flat_map(ObjectNames::indexes) {
            // Every object has a sub-index 0 (CiA 301, section 7.4.3).
            if od.info(index, 0).is_ok() && !indexes.contains(&index) {
                indexes.push(index);
            }
        }
        indexes.sort_unstable();
        let mut eds = Eds::from_dictionary(od, &indexes, |index, sub, _| {
            table_of(tables, index)?.sub(index, sub)
        });
        for o in eds.objects.values_mut() {
            if let Some((name, object_type)) =
                table_of(tables, o.index).and_then(|t| t.object(o.index))
            {
                if !o.subs.is_empty() {
                    o.entry.name = name;
                    o.entry.object_type = object_type;
                }
            }
        }
        let count = |range: core::ops::RangeInclusive<u16>| {
            u16::try_from(indexes.iter().filter(|i| range.contains(i)).count()).unwrap_or(u16::MAX)
        };
        let (rx, tx) = (
            count(RPDO_COMMUNICATION..=RPDO_COMMUNICATION_LAST),
            count(TPDO_COMMUNICATION..=TPDO_COMMUNICATION_LAST),
        );
        let mut name = vec![0u8; 256];
        let product = match od.read(MANUFACTURER_DEVICE_NAME, 0, 0, &mut name) {
            Ok(n) => core::str::from_utf8(name.get(..n).unwrap_or(&[]))
                .ok()
                .and_then(plain)
                .map(ToString::to_string),
            Err(_) => None,
        };
        let [vendor, code, revision] = [1, 2, 3].map(|sub| read_u32(od, IDENTITY, sub));

        let file = &mut eds.file_info;
        file.file_name = plain(header.file_name).map(ToString::to_string);
        file.file_version = Some("1".to_string());
        file.eds_version = Some("4.0".to_string());
        file.description = plain(header.description).map(ToString::to_string);
        file.created_by = Some("canopen-codec".to_string());
        let mut keys = Vec::new();
        if let Some(v) = &file.file_name {
            keys.push(("FileName".to_string(), v.clone()));
        }
        keys.push(("FileVersion".to_string(), "1".to_string()));
        keys.push(("FileRevision".to_string(), "0".to_string()));
        keys.push(("EDSVersion".to_string(), "4.0".to_string()));
        if let Some(v) = &file.description {
            keys.push(("Description".to_string(), v.clone()));
        }
        keys.push(("CreatedBy".to_string(), "canopen-codec".to_string()));
        file.keys = Keys(keys);

        let info = &mut eds.device_info;
        info.vendor_name = header.vendor_name.and_then(plain).map(ToString::to_string);
        info.vendor_number = vendor;
        info.product_name = product;
        info.product_number = code;
        info.revision_number = revision;
        info.baud_rates = vec![10, 20, 50, 125, 250, 500, 800, 1000];
        info.nr_of_rx_pdo = Some(rx);
        info.nr_of_tx_pdo = Some(tx);
        info.lss_supported = false;
        let mut keys = Vec::new();
        if let Some(v) = &info.vendor_name {
            keys.push(("VendorName".to_string(), v.clone()));
        }
        let hex = |v: Option<u32>| format!("0x{:08X}", v.unwrap_or(0));
        keys.push(("VendorNumber".to_string(), hex(vendor)));
        if let Some(v) = &info.product_name {
            keys.push(("ProductName".to_string(), v.clone()));
        }
        keys.push(("ProductNumber".to_string(), hex(code)));
        keys.push(("RevisionNumber".to_string(), hex(revision)));
        for rate in &info.baud_rates {
            keys.push((format!("BaudRate_{rate}"), "1".to_string()));
        }
        for (k, v) in [
            ("SimpleBootUpMaster", "0"),
            ("SimpleBootUpSlave", "1"),
            ("Granularity", "8"),
            ("DynamicChannelsSupported", "0"),
            ("GroupMessaging", "0"),
        ] {
            keys.push((k.to_string(), v.to_string()));
        }
        keys.push(("NrOfRXPDO".to_string(), format!("{rx}")));
        keys.push(("NrOfTXPDO".to_string(), format!("{tx}")));
        keys.push(("LSS_Supported".to_string(), "0".to_string()));
        info.keys = Keys(keys);
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
        let mut od2 = back.dictionary(node);
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
    fn tables_name_runs_and_set_object_types() {
        const SUBS: &[SubDescription] = &[
            SubDescription {
                first: 0,
                last: 0,
                name: "Number of entries",
                data_type: DataType::Unsigned8,
            },
            SubDescription {
                first: 1,
                last: 3,
                name: "Entry",
                data_type: DataType::Unsigned16,
            },
        ];
        const TABLE: &[ObjectDescription] = &[
            ObjectDescription::var(0x1000, "Device type", DataType::Unsigned32),
            ObjectDescription::with_subs(0x2000, 0x2001, "List", ObjectType::Array, SUBS),
        ];
        let mut od = MemoryDictionary::new();
        od.insert(0x1000, 0, Access::Const, &0x1A2u32.to_le_bytes());
        od.insert(0x2001, 0, Access::Const, &[2]);
        od.insert(0x2001, 1, Access::ReadWrite, &7u16.to_le_bytes());
        od.insert(0x2001, 2, Access::ReadWrite, &8u16.to_le_bytes());
        od.insert(0x2001, 9, Access::ReadWrite, &[0; 2]);
        od.insert(0x3000, 0, Access::ReadWrite, &[0]);
        od.insert_variable(0x1008, 0, Access::Const, b"name; with a comment", 32);
        let header = DeviceHeader {
            file_name: "x.eds",
            description: "test",
            vendor_name: Some("Vendor"),
        };
        let eds = Eds::describe(&mut od, &[ObjectNames::Descriptions(TABLE)], &header);
        // 1008h and 3000h are in no table; 2001h sub 9 is in no line.
        assert_eq!(
            eds.objects.keys().copied().collect::<Vec<_>>(),
            [0x1000, 0x2001]
        );
        let list = &eds.objects[&0x2001];
        assert_eq!(list.entry.name, "List 2");
        assert_eq!(list.entry.object_type, ObjectType::Array);
        assert_eq!(eds.name(0x2001, 0), Some("Number of entries"));
        assert_eq!(eds.name(0x2001, 2), Some("Entry 2"));
        assert_eq!(eds.name(0x2001, 9), None);
        assert_eq!(eds.name(0x1000, 0), Some("Device type"));
        assert_eq!(eds.device_info.product_name, None);
        let back = super::super::parse(&super::super::write(&eds)).unwrap();
        assert_eq!(back.device_info.vendor_name.as_deref(), Some("Vendor"));
        assert_eq!(back.device_info.vendor_number, Some(0));
        assert_eq!(back.file_info.file_name.as_deref(), Some("x.eds"));
        assert_eq!(back.warnings, []);
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
