//! Process data objects (PDO), CiA 301: mapping entries and their
//! validation, bit-exact packing, communication parameters, the
//! reconfiguration procedure (device and client side), TPDO timers, the row
//! type of a profile's default PDO set ([`DefaultPdo`]), and named, scaled
//! decoding of PDO fields ([`Catalogue`]).
//!
//! PDOs are numbered from 0 ([`crate::PdoNumber`]): RPDO n has its
//! communication parameters at 1400h + n and mapping at 1600h + n, TPDO n at
//! 1800h + n and 1A00h + n.
//!
//! A PDO frame's bytes are read and written in one place, the PDO wire
//! layer ([`PdoFrame`], and [`Payload`](crate::bytes::Payload) as the
//! crate's [`Codec`](crate::wire::Codec) shape).

mod catalogue;
mod comm;
mod config;
mod defaults;
mod mapping;
mod od_io;
mod pack;
mod producer;
mod reconfig;
mod runtime;
mod wire;

#[cfg(test)]
pub(crate) use catalogue::test_support as catalogue_test_support;
pub use catalogue::{
    Catalogue, FieldValue, Fixed, FlagField, FlagWord, Flags, Formatted, Interpretation, Marker,
    NamedField, NamedFields, Unit, ValueFormat,
};
pub use comm::{
    PdoCobId, PdoCommParams, PdoDirection, SubValue, TransmissionType, TransmissionTypeError,
};
pub use config::{PdoConfig, PdoDictionary, PdoSlot};
pub use defaults::{default_mapping, find_default, DefaultPdo};
pub use mapping::{
    extract_bits, insert_bits, sign_extend, MappingEntry, MappingError, PdoMapping, MAX_BITS,
    MAX_ENTRIES,
};
pub use od_io::{read_mapped, write_mapped, RpdoError};
pub use pack::{FieldError, FieldKind, PackError, UnpackError, Unpacked, Value};
pub use producer::TpdoProducer;
pub use reconfig::{Plan, ReconfigEvent, Reconfigurer, Step};
pub use runtime::{RpdoFrame, RpdoReceiver, TpdoSet};
pub use wire::PdoFrame;
