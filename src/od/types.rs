//! The CiA 301 object codes and data types: what kind of object an index
//! holds (CiA 301, section 7.4.3 "Object code usage": VAR, ARRAY, RECORD,
//! ...) and the data type of a value (section 7.4.7 "Data type entry
//! specification"). An EDS writes them as `ObjectType=` and `DataType=`
//! (CiA 306, section 4.6 "Object descriptions"); the object tables of each
//! area ([`ObjectRow`](super::ObjectRow)) state them once per object.

/// `ObjectType=`: what kind of object a section describes. Absent means
/// [`ObjectType::Var`] (CiA 306, object descriptions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ObjectType {
    /// 0: NULL (an object with no data).
    Null,
    /// 2: DOMAIN.
    Domain,
    /// 5: DEFTYPE (a data type definition).
    DefType,
    /// 6: DEFSTRUCT (a record type definition).
    DefStruct,
    /// 7: VAR, a single value (the default).
    #[default]
    Var,
    /// 8: ARRAY, sub-objects of one type.
    Array,
    /// 9: RECORD, sub-objects of different types.
    Record,
    /// Any other code, kept.
    Other(u8),
}

impl From<u8> for ObjectType {
    fn from(raw: u8) -> Self {
        match raw {
            0 => ObjectType::Null,
            2 => ObjectType::Domain,
            5 => ObjectType::DefType,
            6 => ObjectType::DefStruct,
            7 => ObjectType::Var,
            8 => ObjectType::Array,
            9 => ObjectType::Record,
            other => ObjectType::Other(other),
        }
    }
}

impl From<ObjectType> for u8 {
    fn from(t: ObjectType) -> u8 {
        match t {
            ObjectType::Null => 0,
            ObjectType::Domain => 2,
            ObjectType::DefType => 5,
            ObjectType::DefStruct => 6,
            ObjectType::Var => 7,
            ObjectType::Array => 8,
            ObjectType::Record => 9,
            ObjectType::Other(raw) => raw,
        }
    }
}

impl ObjectType {
    /// True for ARRAY and RECORD (and DEFSTRUCT): objects made of sub-objects.
    #[must_use]
    pub const fn has_subs(self) -> bool {
        matches!(
            self,
            ObjectType::Array | ObjectType::Record | ObjectType::DefStruct
        )
    }
}

/// `DataType=`: the index of a CiA 301 data type (CiA 301, section 7.4.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[allow(missing_docs)] // the variant names are the CiA 301 type names
pub enum DataType {
    Boolean,
    Integer8,
    Integer16,
    Integer32,
    Unsigned8,
    Unsigned16,
    Unsigned32,
    Real32,
    VisibleString,
    OctetString,
    UnicodeString,
    TimeOfDay,
    TimeDifference,
    Domain,
    Integer24,
    Real64,
    Integer40,
    Integer48,
    Integer56,
    Integer64,
    Unsigned24,
    Unsigned40,
    Unsigned48,
    Unsigned56,
    Unsigned64,
    /// Any other index (a DEFTYPE, a DEFSTRUCT, a manufacturer type), kept.
    Other(u16),
}

/// The CiA 301 data types with their indexes, in index order.
const TABLE: [(u16, DataType); 25] = [
    (0x01, DataType::Boolean),
    (0x02, DataType::Integer8),
    (0x03, DataType::Integer16),
    (0x04, DataType::Integer32),
    (0x05, DataType::Unsigned8),
    (0x06, DataType::Unsigned16),
    (0x07, DataType::Unsigned32),
    (0x08, DataType::Real32),
    (0x09, DataType::VisibleString),
    (0x0A, DataType::OctetString),
    (0x0B, DataType::UnicodeString),
    (0x0C, DataType::TimeOfDay),
    (0x0D, DataType::TimeDifference),
    (0x0F, DataType::Domain),
    (0x10, DataType::Integer24),
    (0x11, DataType::Real64),
    (0x12, DataType::Integer40),
    (0x13, DataType::Integer48),
    (0x14, DataType::Integer56),
    (0x15, DataType::Integer64),
    (0x16, DataType::Unsigned24),
    (0x18, DataType::Unsigned40),
    (0x19, DataType::Unsigned48),
    (0x1A, DataType::Unsigned56),
    (0x1B, DataType::Unsigned64),
];

impl From<u16> for DataType {
    fn from(raw: u16) -> Self {
        TABLE
            .iter()
            .find(|(i, _)| *i == raw)
            .map_or(DataType::Other(raw), |(_, t)| *t)
    }
}

impl From<DataType> for u16 {
    fn from(t: DataType) -> u16 {
        if let DataType::Other(raw) = t {
            return raw;
        }
        TABLE.iter().find(|(_, d)| *d == t).map_or(0, |(i, _)| *i)
    }
}

impl DataType {
    /// The size in bytes of a value of a fixed-size type; `None` for the
    /// strings, DOMAIN and unknown types (CiA 301, section 7.1 "Data type
    /// definitions": BOOLEAN takes one byte on the bus).
    #[must_use]
    pub const fn fixed_size(self) -> Option<usize> {
        Some(match self {
            DataType::Boolean | DataType::Integer8 | DataType::Unsigned8 => 1,
            DataType::Integer16 | DataType::Unsigned16 => 2,
            DataType::Integer24 | DataType::Unsigned24 => 3,
            DataType::Integer32 | DataType::Unsigned32 | DataType::Real32 => 4,
            DataType::Integer40 | DataType::Unsigned40 => 5,
            DataType::Integer48
            | DataType::Unsigned48
            | DataType::TimeOfDay
            | DataType::TimeDifference => 6,
            DataType::Integer56 | DataType::Unsigned56 => 7,
            DataType::Integer64 | DataType::Unsigned64 | DataType::Real64 => 8,
            _ => return None,
        })
    }

    /// True for the signed integer types.
    #[must_use]
    pub const fn is_signed(self) -> bool {
        matches!(
            self,
            DataType::Integer8
                | DataType::Integer16
                | DataType::Integer24
                | DataType::Integer32
                | DataType::Integer40
                | DataType::Integer48
                | DataType::Integer56
                | DataType::Integer64
        )
    }

    /// True for the unsigned integer types (BOOLEAN is not one).
    #[must_use]
    pub const fn is_unsigned(self) -> bool {
        matches!(
            self,
            DataType::Unsigned8
                | DataType::Unsigned16
                | DataType::Unsigned24
                | DataType::Unsigned32
                | DataType::Unsigned40
                | DataType::Unsigned48
                | DataType::Unsigned56
                | DataType::Unsigned64
        )
    }

    /// True for VISIBLE_STRING, OCTET_STRING, UNICODE_STRING and DOMAIN,
    /// whose length varies.
    #[must_use]
    pub const fn is_variable(self) -> bool {
        matches!(
            self,
            DataType::VisibleString
                | DataType::OctetString
                | DataType::UnicodeString
                | DataType::Domain
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    #[test]
    fn data_type_codes_round_trip() {
        for raw in 0..=0x30u16 {
            assert_eq!(u16::from(DataType::from(raw)), raw);
        }
        assert_eq!(DataType::from(0x17), DataType::Other(0x17));
        assert_eq!(DataType::from(0x10).fixed_size(), Some(3));
        assert_eq!(DataType::from(0x09).fixed_size(), None);
    }

    /// CiA 301 section 7.4.7: INTEGER8..64 are 0002h-0004h, 0010h, 0012h-0015h;
    /// UNSIGNED8..64 are 0005h-0007h, 0016h, 0018h-001Bh.
    #[test]
    fn signed_and_unsigned_integer_codes() {
        let signed: Vec<u16> = (0..=0x30u16)
            .filter(|&c| DataType::from(c).is_signed())
            .collect();
        let unsigned: Vec<u16> = (0..=0x30u16)
            .filter(|&c| DataType::from(c).is_unsigned())
            .collect();
        assert_eq!(signed, [0x02, 0x03, 0x04, 0x10, 0x12, 0x13, 0x14, 0x15]);
        assert_eq!(unsigned, [0x05, 0x06, 0x07, 0x16, 0x18, 0x19, 0x1A, 0x1B]);
    }

    #[test]
    fn object_type_codes_round_trip() {
        for raw in 0..=255u8 {
            assert_eq!(u8::from(ObjectType::from(raw)), raw);
        }
        assert_eq!(ObjectType::from(9), ObjectType::Record);
    }
}
