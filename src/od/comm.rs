//! The CiA 301 communication objects (1000h-1FFFh) as one table: one
//! [`ObjectRow`] per entry, or per run of sub-indexes (and, for the PDO
//! parameters, of objects) of one shape, with the `ParameterName` and data
//! type CiA 301 gives it ("CANopen application layer and communication
//! profile", section 7.5.2 "Object dictionary entries": 7.5.2.1 device
//! type to 7.5.2.38 TPDO mapping parameter), the access the device core
//! serves it with, its power-on value and the decoder's name for it; and
//! the objects a network manager keeps (CiA 302-2 "Network management",
//! section 4.2, 1F80h-1F89h; CiA 302-3 "Configuration and program
//! download", section 4, 1F22h and 1F52h-1F56h).
//!
//! Derived from these rows: the EDS text of every device
//! ([`Eds::describe`](crate::eds::Eds::describe)), the access rights and
//! power-on values of the device core's objects
//! (`device::CommObjects`) and the names the log analysis gives SDO
//! transfers in the area. Adding a communication object is one row here
//! (and the state that serves it in the device core).
//!
//! ```
//! use canopen_codec::od::comm::COMM_OBJECTS;
//! use canopen_codec::od::{index, Access, Address, DataType, ObjectRow};
//!
//! let heartbeat = ObjectRow::find(COMM_OBJECTS, Address::index(index::PRODUCER_HEARTBEAT_TIME)).unwrap();
//! assert_eq!((heartbeat.name, heartbeat.data_type), ("Producer heartbeat time", DataType::Unsigned16));
//! assert_eq!(heartbeat.access, Access::ReadWrite);
//! // The third TPDO's transmission type: one row for 1800h-19FFh sub 2.
//! let tt = ObjectRow::find(COMM_OBJECTS, Address::new(index::TPDO_COMMUNICATION + 2, 2)).unwrap();
//! assert_eq!(tt.name, "Transmission type");
//! ```

use super::index::{
    BOOT_TIME, CONCISE_DCF, DEVICE_TYPE_IDENTIFICATION, EXPECTED_APPLICATION_SW_DATE,
    EXPECTED_APPLICATION_SW_TIME, EXPECTED_SOFTWARE_IDENTIFICATION, NMT_SLAVE_ASSIGNMENT,
    NMT_STARTUP, PRODUCT_CODE_IDENTIFICATION, REQUEST_NMT, REQUEST_NODE_GUARDING,
    REVISION_NUMBER_IDENTIFICATION, SERIAL_NUMBER_IDENTIFICATION, VENDOR_IDENTIFICATION,
    VERIFY_APPLICATION_SOFTWARE,
};
use super::index::{
    COB_ID_EMCY, COB_ID_SYNC, COB_ID_TIME, COMMUNICATION_CYCLE_PERIOD, CONSUMER_HEARTBEAT_TIME,
    DEVICE_TYPE, ERROR_BEHAVIOUR, ERROR_REGISTER, GUARD_TIME, IDENTITY, INHIBIT_TIME_EMCY,
    LIFE_TIME_FACTOR, MANUFACTURER_DEVICE_NAME, MANUFACTURER_HARDWARE_VERSION,
    MANUFACTURER_SOFTWARE_VERSION, PRE_DEFINED_ERROR_FIELD, PRODUCER_HEARTBEAT_TIME,
    RESTORE_DEFAULT_PARAMETERS, RPDO_COMMUNICATION, RPDO_COMMUNICATION_LAST, RPDO_MAPPING,
    RPDO_MAPPING_LAST, SDO_SERVER_PARAMETER, STORE_PARAMETERS, SYNCHRONOUS_COUNTER_OVERFLOW,
    SYNCHRONOUS_WINDOW_LENGTH, TPDO_COMMUNICATION, TPDO_COMMUNICATION_LAST, TPDO_MAPPING,
    TPDO_MAPPING_LAST,
};
use super::Access::{self, Const, ReadOnly as Ro, ReadWrite as Rw};
use super::DataType::{self, Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use super::ObjectType::{self, Array, Record};
use super::{Address, ObjectRow};
use crate::cob_id::{SYNC, TIME};

/// Sub-index 0 of the ARRAY or RECORD `object` at `index`: the highest
/// sub-index supported, named `short` by the decoder.
const fn highest(
    index: u16,
    object: &'static str,
    object_type: ObjectType,
    access: Access,
    short: &'static str,
) -> ObjectRow {
    ObjectRow::var(index, "Highest sub-index supported", U8, access)
        .heads(object, object_type)
        .short(short)
}

/// Sub-index `sub` of `index`.
const fn at(
    index: u16,
    sub: u8,
    name: &'static str,
    data_type: DataType,
    access: Access,
) -> ObjectRow {
    ObjectRow::new(Address::new(index, sub), name, data_type, access)
}

/// The RPDO or TPDO parameters, one direction's nine rows: the
/// communication parameters `communication.0` to `communication.1` (CiA
/// 301, 7.5.2.35 and 7.5.2.37), then the mapping parameters `mapping.0` to
/// `mapping.1` with the number of entries and up to 64 entries (7.5.2.36
/// and 7.5.2.38). `names` are the communication object's, its COB-ID
/// entry's and the mapping object's.
const fn pdo_parameters(
    communication: (u16, u16),
    mapping: (u16, u16),
    names: [&'static str; 3],
) -> [ObjectRow; 9] {
    let ((first, last), (map, map_last)) = (communication, mapping);
    let [object, cob_id, map_object] = names;
    [
        highest(first, object, Record, Ro, "highest sub-index").indexes_through(last),
        at(first, 1, cob_id, U32, Rw).indexes_through(last),
        at(first, 2, "Transmission type", U8, Rw).indexes_through(last),
        at(first, 3, "Inhibit time", U16, Rw).indexes_through(last),
        at(first, 4, "Compatibility entry", U8, Rw).indexes_through(last),
        at(first, 5, "Event-timer", U16, Rw).indexes_through(last),
        at(first, 6, "SYNC start value", U8, Rw).indexes_through(last),
        ObjectRow::var(map, "Number of mapped application objects in PDO", U8, Rw)
            .heads(map_object, Record)
            .short("number of entries")
            .indexes_through(map_last),
        at(map, 1, "Application object", U32, Rw)
            .through(64)
            .indexes_through(map_last),
    ]
}

const RPDO_ROWS: [ObjectRow; 9] = pdo_parameters(
    (RPDO_COMMUNICATION, RPDO_COMMUNICATION_LAST),
    (RPDO_MAPPING, RPDO_MAPPING_LAST),
    [
        "RPDO communication parameter",
        "COB-ID used by RPDO",
        "RPDO mapping parameter",
    ],
);
const TPDO_ROWS: [ObjectRow; 9] = pdo_parameters(
    (TPDO_COMMUNICATION, TPDO_COMMUNICATION_LAST),
    (TPDO_MAPPING, TPDO_MAPPING_LAST),
    [
        "TPDO communication parameter",
        "COB-ID used by TPDO",
        "TPDO mapping parameter",
    ],
);

/// The rows of `rows` one after the other (`N` their total length).
const fn joined<const N: usize>(parts: &[&[ObjectRow]]) -> [ObjectRow; N] {
    let mut out = [ObjectRow::var(0, "", U8, Const); N];
    let (mut part, mut n) = (0, 0);
    while part < parts.len() {
        let mut i = 0;
        while i < parts[part].len() {
            out[n] = parts[part][i];
            n += 1;
            i += 1;
        }
        part += 1;
    }
    assert!(n == N, "the joined length is the sum of the parts");
    out
}

/// The objects of 1000h-100Dh (and, after [`STORE_ROWS`] and
/// [`RESTORE_ROWS`], those of 1012h-1200h), in index order: those the
/// device core serves, and the error behaviour, EMCY and version objects it does not
/// but a log analysis names. A value that depends on the node id (1014h,
/// 1200h sub 1 and 2: 80h, 600h, 580h + node id) has no power-on value in
/// its row.
const OBJECTS_TO_100D: &[ObjectRow] = &[
    ObjectRow::var(DEVICE_TYPE, "Device type", U32, Const).short("device type"),
    ObjectRow::var(ERROR_REGISTER, "Error register", U8, Ro).short("error register"),
    ObjectRow::var(PRE_DEFINED_ERROR_FIELD, "Number of errors", U8, Rw)
        .heads("Pre-defined error field", Array)
        .short("number of errors"),
    at(PRE_DEFINED_ERROR_FIELD, 1, "Standard error field", U32, Ro)
        .through(254)
        .short("pre-defined error field"),
    ObjectRow::var(COB_ID_SYNC, "COB-ID SYNC message", U32, Rw)
        .short("COB-ID SYNC")
        .default(SYNC as u32),
    ObjectRow::var(
        COMMUNICATION_CYCLE_PERIOD,
        "Communication cycle period",
        U32,
        Rw,
    )
    .short("communication cycle period"),
    ObjectRow::var(
        SYNCHRONOUS_WINDOW_LENGTH,
        "Synchronous window length",
        U32,
        Rw,
    )
    .short("synchronous window length"),
    ObjectRow::var(
        MANUFACTURER_DEVICE_NAME,
        "Manufacturer device name",
        DataType::VisibleString,
        Const,
    )
    .short("manufacturer device name"),
    ObjectRow::var(
        MANUFACTURER_HARDWARE_VERSION,
        "Manufacturer hardware version",
        DataType::VisibleString,
        Const,
    )
    .short("manufacturer hardware version"),
    ObjectRow::var(
        MANUFACTURER_SOFTWARE_VERSION,
        "Manufacturer software version",
        DataType::VisibleString,
        Const,
    )
    .short("manufacturer software version"),
    ObjectRow::var(GUARD_TIME, "Guard time", U16, Rw).short("guard time"),
    ObjectRow::var(LIFE_TIME_FACTOR, "Life time factor", U8, Rw).short("life time factor"),
];

/// 1010h store parameters and 1011h restore default parameters: the
/// highest sub-index (3, power-on value), then one entry per parameter
/// group CiA 301 gives both objects (sections 7.5.2.13 and 7.5.2.14): sub 1
/// all parameters, sub 2 the communication parameters (1000h-1FFFh), sub 3
/// the application parameters (6000h-9FFFh). `names` are the object's and
/// its three groups' entries'; `short` is the decoder's name for sub 0.
const fn parameter_groups(
    index: u16,
    names: [&'static str; 4],
    short: &'static str,
) -> [ObjectRow; 4] {
    let [object, all, communication, application] = names;
    [
        highest(index, object, Array, Const, short).default(3),
        at(index, 1, all, U32, Rw),
        at(index, 2, communication, U32, Rw),
        at(index, 3, application, U32, Rw),
    ]
}

const STORE_ROWS: [ObjectRow; 4] = parameter_groups(
    STORE_PARAMETERS,
    [
        "Store parameters",
        "Save all parameters",
        "Save communication parameters",
        "Save application parameters",
    ],
    "store parameters: highest sub-index",
);
const RESTORE_ROWS: [ObjectRow; 4] = parameter_groups(
    RESTORE_DEFAULT_PARAMETERS,
    [
        "Restore default parameters",
        "Restore all default parameters",
        "Restore communication default parameters",
        "Restore application default parameters",
    ],
    "restore default parameters: highest sub-index",
);

/// The objects of 1012h-1200h, in index order (see [`OBJECTS_TO_100D`]).
const OBJECTS_FROM_1012: &[ObjectRow] = &[
    ObjectRow::var(COB_ID_TIME, "COB-ID time stamp object", U32, Rw)
        .short("COB-ID TIME")
        .default(TIME as u32),
    ObjectRow::var(COB_ID_EMCY, "COB-ID EMCY", U32, Rw).short("COB-ID EMCY"),
    ObjectRow::var(INHIBIT_TIME_EMCY, "Inhibit time EMCY", U16, Rw).short("inhibit time EMCY"),
    highest(
        CONSUMER_HEARTBEAT_TIME,
        "Consumer heartbeat time",
        Array,
        Const,
        "consumer heartbeat time: highest sub-index",
    ),
    at(
        CONSUMER_HEARTBEAT_TIME,
        1,
        "Consumer heartbeat time",
        U32,
        Rw,
    )
    .through(127)
    .short("consumer heartbeat time"),
    ObjectRow::var(PRODUCER_HEARTBEAT_TIME, "Producer heartbeat time", U16, Rw)
        .short("producer heartbeat time"),
    highest(
        IDENTITY,
        "Identity object",
        Record,
        Ro,
        "identity: highest sub-index",
    )
    .default(4),
    at(IDENTITY, 1, "Vendor-ID", U32, Ro).short("identity vendor-ID"),
    at(IDENTITY, 2, "Product code", U32, Ro).short("identity product code"),
    at(IDENTITY, 3, "Revision number", U32, Ro).short("identity revision number"),
    at(IDENTITY, 4, "Serial number", U32, Ro).short("identity serial number"),
    ObjectRow::var(
        SYNCHRONOUS_COUNTER_OVERFLOW,
        "Synchronous counter overflow value",
        U8,
        Rw,
    )
    .short("synchronous counter overflow value"),
    highest(
        ERROR_BEHAVIOUR,
        "Error behavior object",
        Array,
        Const,
        "error behaviour: highest sub-index",
    ),
    at(ERROR_BEHAVIOUR, 1, "Communication error", U8, Rw),
    at(ERROR_BEHAVIOUR, 2, "Error class", U8, Rw).through(0xFE),
    highest(
        SDO_SERVER_PARAMETER,
        "SDO server parameter",
        Record,
        Ro,
        "SDO server parameter 0: highest sub-index",
    )
    .default(2),
    at(
        SDO_SERVER_PARAMETER,
        1,
        "COB-ID client to server (rx)",
        U32,
        Ro,
    ),
    at(
        SDO_SERVER_PARAMETER,
        2,
        "COB-ID server to client (tx)",
        U32,
        Ro,
    ),
    at(SDO_SERVER_PARAMETER, 3, "Node-ID of the SDO client", U8, Ro),
];

/// An ARRAY of the NMT master with one `data_type` entry per node 1-127
/// (CiA 302-2 "Network management", section 4.2): the highest sub-index
/// (127) and the run of entries, named `name` (`short` for the decoder,
/// which adds "of node N").
const fn per_node(
    index: u16,
    name: &'static str,
    short: &'static str,
    data_type: DataType,
    access: Access,
) -> [ObjectRow; 2] {
    [
        ObjectRow::var(index, "Highest sub-index supported", U8, Const)
            .heads(name, Array)
            .short(short)
            .default(127),
        at(index, 1, name, data_type, access)
            .through(127)
            .short(short),
    ]
}

/// The configuration manager's and NMT master's objects of CiA 302-2
/// "Network management" (section 4.2: 1F80h-1F89h) and CiA 302-3
/// "Configuration and program download" (section 4: 1F22h, 1F52h-1F56h),
/// in index order. No device of ours serves them; the boot-up manager
/// keeps their values in its configuration (`manager::ManagerConfig`,
/// `NodeConfig`), and the log analysis names them by these rows.
const MANAGER_ROWS: [ObjectRow; 31] = joined::<31>(&[
    &[
        ObjectRow::var(CONCISE_DCF, "Highest sub-index supported", U8, Const)
            .heads("Concise DCF", Array)
            .short("concise DCF")
            .default(127),
        at(CONCISE_DCF, 1, "Concise DCF", DataType::Domain, Rw)
            .through(127)
            .short("concise DCF"),
        ObjectRow::var(
            VERIFY_APPLICATION_SOFTWARE,
            "Highest sub-index supported",
            U8,
            Const,
        )
        .heads("Verify application software", Record)
        .short("verify application software")
        .default(2),
        at(
            VERIFY_APPLICATION_SOFTWARE,
            1,
            "Application software date",
            U32,
            Rw,
        )
        .short("verify application software: date"),
        at(
            VERIFY_APPLICATION_SOFTWARE,
            2,
            "Application software time",
            U32,
            Rw,
        )
        .short("verify application software: time"),
    ],
    &per_node(
        EXPECTED_APPLICATION_SW_DATE,
        "Expected application SW date",
        "expected application software date",
        U32,
        Rw,
    ),
    &per_node(
        EXPECTED_APPLICATION_SW_TIME,
        "Expected application SW time",
        "expected application software time",
        U32,
        Rw,
    ),
    &per_node(
        EXPECTED_SOFTWARE_IDENTIFICATION,
        "Expected software identification",
        "expected software identification",
        U32,
        Rw,
    ),
    &[
        ObjectRow::var(0x1F56, "Highest sub-index supported", U8, Const)
            .heads("Program software identification", Array)
            .short("program software identification")
            .default(1),
        at(0x1F56, 1, "Program software identification", U32, Ro)
            .through(0xFE)
            .short("program software identification"),
        ObjectRow::var(NMT_STARTUP, "NMT start-up", U32, Rw).short("NMT start-up"),
    ],
    &per_node(
        NMT_SLAVE_ASSIGNMENT,
        "NMT slave assignment",
        "NMT slave assignment",
        U32,
        Rw,
    ),
    &[
        ObjectRow::var(REQUEST_NMT, "Highest sub-index supported", U8, Const)
            .heads("Request NMT", Array)
            .short("request NMT")
            .default(128),
        at(REQUEST_NMT, 1, "Request NMT", U8, Rw)
            .through(128)
            .short("request NMT"),
        ObjectRow::var(
            REQUEST_NODE_GUARDING,
            "Highest sub-index supported",
            U8,
            Const,
        )
        .heads("Request node guarding", Array)
        .short("request node guarding")
        .default(128),
        at(REQUEST_NODE_GUARDING, 1, "Request node guarding", U8, Rw)
            .through(128)
            .short("request node guarding"),
    ],
    &per_node(
        DEVICE_TYPE_IDENTIFICATION,
        "Device type identification",
        "device type identification",
        U32,
        Rw,
    ),
    &per_node(
        VENDOR_IDENTIFICATION,
        "Vendor identification",
        "vendor identification",
        U32,
        Rw,
    ),
    &per_node(
        PRODUCT_CODE_IDENTIFICATION,
        "Product code",
        "product code",
        U32,
        Rw,
    ),
    &per_node(
        REVISION_NUMBER_IDENTIFICATION,
        "Revision number",
        "revision number",
        U32,
        Rw,
    ),
    &per_node(
        SERIAL_NUMBER_IDENTIFICATION,
        "Serial number",
        "serial number",
        U32,
        Rw,
    ),
    &[ObjectRow::var(BOOT_TIME, "Boot time", U32, Rw).short("boot time")],
]);

/// The number of rows of [`COMM_OBJECTS`].
const ROWS: usize = OBJECTS_TO_100D.len()
    + STORE_ROWS.len()
    + RESTORE_ROWS.len()
    + OBJECTS_FROM_1012.len()
    + RPDO_ROWS.len()
    + TPDO_ROWS.len()
    + MANAGER_ROWS.len();

/// The CiA 301 communication objects: those of the device core (1000h,
/// 1001h, 1003h, 1005h-1008h, 100Ch, 100Dh, 1010h, 1011h, 1012h,
/// 1016h-1019h, 1200h), the version, EMCY and error behaviour objects
/// (1009h, 100Ah, 1014h, 1015h, 1029h), the PDO communication and
/// mapping parameters (1400h-1BFFh) and the CiA 302-2/302-3 objects of a
/// network manager (1F22h, 1F52h-1F56h, 1F80h-1F89h), in index order (see
/// the [module docs](self)).
pub const COMM_OBJECTS: &[ObjectRow] = &joined::<ROWS>(&[
    OBJECTS_TO_100D,
    &STORE_ROWS,
    &RESTORE_ROWS,
    OBJECTS_FROM_1012,
    &RPDO_ROWS,
    &TPDO_ROWS,
    &MANAGER_ROWS,
]);

/// The row of [`COMM_OBJECTS`] that covers `address`, if any: what
/// [`ObjectRow::find`] finds, as a `const fn` for facts a program reads at
/// build time (`const { comm::find(..) }`).
#[must_use]
pub const fn find(address: Address) -> Option<&'static ObjectRow> {
    let mut i = 0;
    while i < COMM_OBJECTS.len() {
        if COMM_OBJECTS[i].covers(address.index, address.sub) {
            return Some(&COMM_OBJECTS[i]);
        }
        i += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abort::AbortCode;

    #[test]
    fn rows_in_order_each_entry_once_and_every_object_with_a_sub_0() {
        for pair in COMM_OBJECTS.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let after = (b.address.index, b.address.sub) > (a.address.index, a.last_sub)
                || b.address.index > a.last_index;
            assert!(after, "{} after {}", b.address, a.address);
        }
        for row in COMM_OBJECTS {
            let head = find(Address::new(row.address.index, 0)).expect("a sub-index 0 row");
            assert_eq!(head.last_index, row.last_index, "{}", row.address);
            let variable = [DataType::VisibleString, DataType::Domain];
            assert!(row.size() > 0 || variable.contains(&row.data_type));
            assert_eq!(find(row.address), Some(row));
        }
    }

    #[test]
    fn a_pdo_parameter_row_covers_its_512_objects() {
        for (first, last) in [
            (RPDO_COMMUNICATION, RPDO_COMMUNICATION_LAST),
            (RPDO_MAPPING, RPDO_MAPPING_LAST),
            (TPDO_COMMUNICATION, TPDO_COMMUNICATION_LAST),
            (TPDO_MAPPING, TPDO_MAPPING_LAST),
        ] {
            assert_eq!(last - first + 1, 512);
            let head = find(Address::index(first)).unwrap();
            assert_eq!(find(Address::index(last)), Some(head));
            assert_eq!(head.entry_count(), 512);
            assert_ne!(find(Address::index(last + 1)), Some(head));
            assert_ne!(find(Address::index(first - 1)), Some(head));
        }
        // RPDO and TPDO parameters alike (the PDO layer reads the TPDO
        // rows for both).
        for sub in 0..=u8::MAX {
            let access = |index| find(Address::new(index, sub)).map(|r| (r.access, r.data_type));
            assert_eq!(
                access(RPDO_COMMUNICATION),
                access(TPDO_COMMUNICATION),
                "sub {sub}"
            );
            assert_eq!(access(RPDO_MAPPING), access(TPDO_MAPPING), "sub {sub}");
        }
        let entry = find(Address::new(RPDO_MAPPING + 7, 64)).unwrap();
        assert_eq!((entry.name, entry.data_type), ("Application object", U32));
        assert_eq!(find(Address::new(RPDO_MAPPING, 65)), None);
    }

    #[test]
    fn the_const_lookup_agrees_with_object_row_find() {
        for index in 0x1000..=0x1FFFu16 {
            for sub in [0, 1, 2, 3, 4, 6, 7, 64, 65, 127, 128, 254, 255] {
                let address = Address::new(index, sub);
                let found = ObjectRow::find(COMM_OBJECTS, address);
                assert_eq!(found.ok(), find(address), "{address}");
                if let Err(abort) = found {
                    let object = find(Address::index(index)).is_some();
                    let want = if object {
                        AbortCode::SubIndexDoesNotExist
                    } else {
                        AbortCode::ObjectDoesNotExist
                    };
                    assert_eq!(abort, want, "{address}");
                }
            }
        }
    }
}
