//! One row of an object table: every fact of one object-dictionary entry
//! (or of a run of sub-indexes of the same shape), stated once
//! ([`ObjectRow`]).

use super::{Access, Address, DataType, FixedEntry, Interpretation, Marker, ObjectType, Unit};
use crate::abort::AbortCode;

/// The ARRAY or RECORD that a sub-index 0 row heads: the object's own
/// `ParameterName` and object code (CiA 301, section 7.4.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Compound {
    /// The object's `ParameterName` (its sub-objects have their own).
    pub name: &'static str,
    /// [`ObjectType::Array`] or [`ObjectType::Record`].
    pub object_type: ObjectType,
}

/// The row's builder methods that set one of its fields: `name(field:
/// type)` is a `const fn` taking the row and the field's new value.
macro_rules! setters {
    ($($(#[$doc:meta])* $name:ident($field:ident: $ty:ty);)*) => {
        $(
            $(#[$doc])*
            #[must_use]
            pub const fn $name(mut self, $field: $ty) -> Self {
                self.$field = $field;
                self
            }
        )*
    };
}

/// Every fact of one object-dictionary entry, or of a run of sub-indexes
/// of the same shape.
///
/// Each area (the CiA 301 communication objects, CiA 418, CiA 419, the
/// Delta-Q charger) declares its objects as one table of [`ObjectRow`]s,
/// and everything else is derived from the rows, found by [`Address`],
/// never matched by position: the dictionary's SDO answers (access,
/// length, PDO mapping, power-on value, which entries NMT reset node
/// restores), the EDS text (`ParameterName`, `DataType`, `ObjectType`:
/// CiA 306 section 4.6), the PDO decoder's names, units and scales
/// ([`crate::pdo::Catalogue`]) and the tests, which iterate the table.
/// Adding an object is adding one row.
///
/// A row holds:
///
/// - the [`Address`] of its first sub-index, and the last sub-index of the
///   run it covers (the same sub-index for one entry);
/// - the name the defining document (and so its EDS) spells
///   (`ParameterName`) and the decoder's short name in lower-case words
///   (`charging current`; the same as the spec's name unless set);
/// - the CiA 301 [`DataType`] (section 7.4.7), the [`Access`] and whether a
///   PDO may map it (section 7.4.8);
/// - the default value (the power-on value of a fixed-size entry, its
///   little-endian word);
/// - how to read the value in words ([`Interpretation`]: scale, unit,
///   marker, flag word or a profile's format);
/// - for the sub-index 0 row of an ARRAY or RECORD, the object it heads
///   ([`Compound`]: the object's own name and object code).
///
/// Rows are `const` data built with `const fn`s:
///
/// ```
/// use canopen_codec::od::{Access, Address, DataType, ObjectRow, ObjectType};
/// use canopen_codec::pdo::{Interpretation, Marker, Unit};
///
/// /// A made-up device: a bus voltage (2000h, U16 in 1/16 V, 0xFFFF no
/// /// value) and a RECORD of two limits (2001h).
/// const ROWS: &[ObjectRow] = &[
///     ObjectRow::var(0x2000, "Bus Voltage", DataType::Unsigned16, Access::ReadOnly)
///         .short("bus voltage")
///         .mappable()
///         .default(0xFFFF)
///         .scaled(4, Some(Unit::Volt))
///         .marked(Marker::NoValue(0xFFFF), None),
///     ObjectRow::var(0x2001, "Number of entries", DataType::Unsigned8, Access::Const)
///         .heads("Limits", ObjectType::Record)
///         .default(2),
///     ObjectRow::new(Address::new(0x2001, 1), "Limit", DataType::Unsigned16, Access::ReadWrite)
///         .through(2),
/// ];
///
/// let voltage = ObjectRow::find(ROWS, Address::index(0x2000)).unwrap();
/// assert_eq!((voltage.bits(), voltage.size(), voltage.short), (16, 2, "bus voltage"));
/// assert!(matches!(voltage.interpretation, Interpretation::Unsigned { frac_bits: 4, .. }));
/// // A run of sub-indexes: 2001h sub 1 and 2 share one row.
/// let limit = ObjectRow::find(ROWS, Address::new(0x2001, 2)).unwrap();
/// assert_eq!(limit.name, "Limit");
/// // What an SDO server answers for what the table lacks (CiA 301 7.2.4.3.17).
/// use canopen_codec::sdo::AbortCode;
/// assert_eq!(ObjectRow::find(ROWS, Address::new(0x2001, 3)), Err(AbortCode::SubIndexDoesNotExist));
/// assert_eq!(ObjectRow::find(ROWS, Address::index(0x2002)), Err(AbortCode::ObjectDoesNotExist));
/// // What reset node restores: the writable entries, 2 bytes each.
/// assert_eq!(ObjectRow::parameter_count(ROWS), 2);
/// assert_eq!(ObjectRow::parameter_bytes(ROWS), 4);
/// // The objects, each once: 2001h has two rows.
/// assert_eq!(ObjectRow::object_count(ROWS), 2);
/// assert_eq!(ObjectRow::object_indexes::<2>(ROWS), [0x2000, 0x2001]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ObjectRow {
    /// The entry, or the first of the run.
    pub address: Address,
    /// The last sub-index of the run (`address.sub` for one entry).
    pub last_sub: u8,
    /// The last index of a run of objects of one shape (`address.index`
    /// for one object): the PDO parameters 1400h-15FFh, for one, are 512
    /// objects with the same sub-indexes (CiA 301, 7.5.2.35). An EDS
    /// appends `" <n>"`, from 1 at `address.index`, to their object names.
    pub last_index: u16,
    /// `ParameterName` as the defining document spells it; for a run,
    /// an EDS appends `" <sub>"`.
    pub name: &'static str,
    /// The decoder's name in lower-case words (`2002h charging current`).
    pub short: &'static str,
    /// The CiA 301 data type.
    pub data_type: DataType,
    /// The access rights.
    pub access: Access,
    /// True if a PDO may map it.
    pub mappable: bool,
    /// The power-on value: a fixed-size entry's value as a little-endian
    /// word (its first [`size`](Self::size) bytes); 0 otherwise.
    pub default: u32,
    /// How to read the value in words.
    pub interpretation: Interpretation,
    /// The ARRAY or RECORD this sub-index 0 row heads, if any.
    pub compound: Option<Compound>,
}

impl ObjectRow {
    /// The entry at `address` named `name`, of type `data_type` with
    /// access `access`: not PDO-mappable, default 0, read as a plain
    /// integer of its type (unsigned unless the type is signed).
    #[must_use]
    pub const fn new(
        address: Address,
        name: &'static str,
        data_type: DataType,
        access: Access,
    ) -> Self {
        ObjectRow {
            address,
            last_sub: address.sub,
            last_index: address.index,
            name,
            short: name,
            data_type,
            access,
            mappable: false,
            default: 0,
            interpretation: plain(data_type, 0, None),
            compound: None,
        }
    }

    /// Sub-index 0 of `index` (a VAR, or the count of an ARRAY or RECORD):
    /// [`new`](Self::new).
    #[must_use]
    pub const fn var(index: u16, name: &'static str, data_type: DataType, access: Access) -> Self {
        Self::new(Address::index(index), name, data_type, access)
    }

    setters! {
        /// This row covering the sub-indexes up to `last_sub` too.
        through(last_sub: u8);
        /// This row covering the objects up to `last_index` too, each with
        /// the same sub-indexes.
        indexes_through(last_index: u16);
        /// This row with the decoder's name `short`.
        short(short: &'static str);
        /// This row with the power-on value `default` (its little-endian
        /// word).
        default(default: u32);
    }

    /// This row PDO-mappable.
    #[must_use]
    pub const fn mappable(mut self) -> Self {
        self.mappable = true;
        self
    }

    /// This row read as `raw / 2^frac_bits` in `unit` (signed if its data
    /// type is), no marker, no range limit.
    #[must_use]
    pub const fn scaled(mut self, frac_bits: u8, unit: Option<Unit>) -> Self {
        self.interpretation = plain(self.data_type, frac_bits, unit);
        self
    }

    /// This unsigned row with a marker and a largest raw value in range
    /// (other interpretations are left unchanged).
    #[must_use]
    pub const fn marked(mut self, marker: Marker, range_max: Option<u64>) -> Self {
        if let Interpretation::Unsigned {
            frac_bits, unit, ..
        } = self.interpretation
        {
            self.interpretation = Interpretation::Unsigned {
                frac_bits,
                unit,
                marker,
                max: range_max,
            };
        }
        self
    }

    /// This row read as `interpretation`.
    #[must_use]
    pub const fn reading(mut self, interpretation: Interpretation) -> Self {
        self.interpretation = interpretation;
        self
    }

    /// This sub-index 0 row heading the ARRAY or RECORD `name`.
    #[must_use]
    pub const fn heads(mut self, name: &'static str, object_type: ObjectType) -> Self {
        self.compound = Some(Compound { name, object_type });
        self
    }

    /// The size of a value in bytes (0 for a variable-size type).
    #[must_use]
    pub const fn size(&self) -> u8 {
        match self.data_type.fixed_size() {
            Some(n) if n <= 8 => n as u8,
            _ => 0,
        }
    }

    /// The size a PDO maps the value at, in bits: a BOOLEAN is one bit,
    /// the other fixed-size types their bytes times 8 (0 for a
    /// variable-size type).
    #[must_use]
    pub const fn bits(&self) -> u8 {
        match self.data_type {
            DataType::Boolean => 1,
            _ => self.size().saturating_mul(8),
        }
    }

    /// True if this row describes `index` sub `sub`.
    #[must_use]
    pub const fn covers(&self, index: u16, sub: u8) -> bool {
        self.covers_index(index) && sub >= self.address.sub && sub <= self.last_sub
    }

    /// True if this row describes some sub-index of object `index`.
    #[must_use]
    pub const fn covers_index(&self, index: u16) -> bool {
        index >= self.address.index && index <= self.last_index
    }

    /// How many sub-indexes the row covers in each of its objects.
    #[must_use]
    pub const fn sub_count(&self) -> usize {
        (self.last_sub as usize + 1).saturating_sub(self.address.sub as usize)
    }

    /// How many entries the row covers: its sub-indexes in each of its
    /// objects.
    #[must_use]
    pub const fn entry_count(&self) -> usize {
        let objects = (self.last_index as usize + 1).saturating_sub(self.address.index as usize);
        objects * self.sub_count()
    }

    /// True for a parameter: an entry an SDO download or an RPDO can
    /// change, which NMT reset node sets back to its value at boot (CiA
    /// 301 7.3.2.2.1). A writable padding entry
    /// ([`Interpretation::Padding`]) stores nothing and is not one.
    #[must_use]
    pub const fn is_parameter(&self) -> bool {
        self.access.is_writable() && !matches!(self.interpretation, Interpretation::Padding)
    }

    /// The entry a fixed-word dictionary serves for this row holding
    /// `word` (CiA 301 basic types up to 4 bytes).
    #[must_use]
    pub const fn entry(&self, word: u32) -> FixedEntry {
        FixedEntry {
            access: self.access,
            word,
            len: self.size(),
            mappable: self.mappable,
            slot: 0,
        }
    }

    /// The row of `rows` that covers `address`; a missing sub-index of an
    /// object the table has is 06090011h, a missing object 06020000h
    /// (CiA 301 7.2.4.3.17).
    pub fn find(rows: &[ObjectRow], address: Address) -> Result<&ObjectRow, AbortCode> {
        let Address { index, sub } = address;
        if let Some(row) = rows.iter().find(|r| r.covers(index, sub)) {
            return Ok(row);
        }
        Err(if rows.iter().any(|r| r.covers_index(index)) {
            AbortCode::SubIndexDoesNotExist
        } else {
            AbortCode::ObjectDoesNotExist
        })
    }

    /// How many objects `rows` describe: each index once, however many
    /// rows (sub-indexes) it has.
    #[must_use]
    pub const fn object_count(rows: &[ObjectRow]) -> usize {
        let mut list = [0u16; 0];
        Self::objects_into(rows, &mut list)
    }

    /// The indexes of the objects `rows` describe, each once, in the order
    /// of their first row; `N` is [`object_count`](Self::object_count)
    /// (indexes past it are left out, missing ones are 0).
    #[must_use]
    pub const fn object_indexes<const N: usize>(rows: &[ObjectRow]) -> [u16; N] {
        let mut list = [0u16; N];
        Self::objects_into(rows, &mut list);
        list
    }

    /// Writes the indexes of the objects of `rows` into `list` (as many as
    /// fit) and counts them all.
    const fn objects_into(rows: &[ObjectRow], list: &mut [u16]) -> usize {
        let (mut i, mut n) = (0, 0);
        while i < rows.len() {
            let mut index = rows[i].address.index;
            while index <= rows[i].last_index {
                // Seen before: an earlier row of the same object.
                let mut seen = false;
                let mut j = 0;
                while j < i {
                    seen |= rows[j].covers_index(index);
                    j += 1;
                }
                if !seen {
                    if n < list.len() {
                        list[n] = index;
                    }
                    n += 1;
                }
                if index == u16::MAX {
                    break;
                }
                index += 1;
            }
            i += 1;
        }
        n
    }

    /// How many entries of `rows` are parameters
    /// ([`is_parameter`](Self::is_parameter)), each sub-index of a run
    /// counted.
    #[must_use]
    pub const fn parameter_count(rows: &[ObjectRow]) -> usize {
        Self::sum_parameters(rows, false)
    }

    /// The bytes of the values of the parameters of `rows`, one after the
    /// other.
    #[must_use]
    pub const fn parameter_bytes(rows: &[ObjectRow]) -> usize {
        Self::sum_parameters(rows, true)
    }

    /// The parameter entries of `rows`, each counted as its size in bytes
    /// (`bytes`) or as one.
    const fn sum_parameters(rows: &[ObjectRow], bytes: bool) -> usize {
        let (mut i, mut n) = (0, 0);
        while i < rows.len() {
            let row = &rows[i];
            if row.is_parameter() {
                let each = if bytes { row.size() as usize } else { 1 };
                n += row.entry_count() * each;
            }
            i += 1;
        }
        n
    }

    /// The `(index, sub)` of the parameters of `rows`, in row order; `N`
    /// is [`parameter_count`](Self::parameter_count) (entries past it are
    /// left out, missing ones are `(0, 0)`).
    #[must_use]
    pub const fn parameters<const N: usize>(rows: &[ObjectRow]) -> [(u16, u8); N] {
        let mut list = [(0u16, 0u8); N];
        let (mut i, mut n) = (0, 0);
        while i < rows.len() {
            let row = rows[i];
            let mut index = row.address.index;
            while row.is_parameter() && index <= row.last_index {
                let mut sub = row.address.sub;
                while sub <= row.last_sub && n < N {
                    list[n] = (index, sub);
                    n += 1;
                    if sub == u8::MAX {
                        break;
                    }
                    sub += 1;
                }
                if index == u16::MAX {
                    break;
                }
                index += 1;
            }
            i += 1;
        }
        list
    }
}

/// `raw / 2^frac_bits` in `unit`, signed if `data_type` is.
const fn plain(data_type: DataType, frac_bits: u8, unit: Option<Unit>) -> Interpretation {
    if data_type.is_signed() {
        Interpretation::Signed { frac_bits, unit }
    } else {
        Interpretation::Unsigned {
            frac_bits,
            unit,
            marker: Marker::None,
            max: None,
        }
    }
}
