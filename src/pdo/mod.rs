//! Process data objects (PDO), CiA 301: mapping entries and their
//! validation, bit-exact packing, communication parameters.
//!
//! PDOs are numbered from 0 ([`crate::PdoNumber`]): RPDO n has its
//! communication parameters at 1400h + n and mapping at 1600h + n, TPDO n at
//! 1800h + n and 1A00h + n.

mod comm;
mod mapping;
mod pack;

pub use comm::{PdoCobId, PdoCommParams, SubValue, TransmissionType, TransmissionTypeError};
pub use mapping::{
    extract_bits, insert_bits, sign_extend, MappingEntry, MappingError, PdoMapping, MAX_BITS,
    MAX_ENTRIES,
};
pub use pack::{FieldError, FieldKind, PackError, UnpackError, Unpacked, Value};
