//! The names and data types of the CiA 301 objects the device core serves
//! (1000h-1FFFh), for describing a device as an EDS
//! ([`Eds::describe`](crate::eds::Eds::describe)).

use crate::eds::DataType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use crate::eds::{sub, DataType, ObjectDescription, ObjectType, SubDescription};
use crate::od::index::{
    COB_ID_SYNC, COB_ID_TIME, COMMUNICATION_CYCLE_PERIOD, CONSUMER_HEARTBEAT_TIME, DEVICE_TYPE,
    ERROR_REGISTER, GUARD_TIME, IDENTITY, LIFE_TIME_FACTOR, MANUFACTURER_DEVICE_NAME,
    PRE_DEFINED_ERROR_FIELD, PRODUCER_HEARTBEAT_TIME, RESTORE_DEFAULT_PARAMETERS,
    RPDO_COMMUNICATION, RPDO_COMMUNICATION_LAST, RPDO_MAPPING, RPDO_MAPPING_LAST,
    SDO_SERVER_PARAMETER, STORE_PARAMETERS, SYNCHRONOUS_COUNTER_OVERFLOW,
    SYNCHRONOUS_WINDOW_LENGTH, TPDO_COMMUNICATION, TPDO_COMMUNICATION_LAST, TPDO_MAPPING,
    TPDO_MAPPING_LAST,
};

const HIGHEST: SubDescription = sub(0, 0, "Highest sub-index supported", U8);

/// The sub-objects of an RPDO or a TPDO communication parameter (CiA 301,
/// 7.5.2.35 and 7.5.2.37), sub-index 1 named `cob_id`.
const fn pdo_comm(cob_id: &'static str) -> [SubDescription; 7] {
    [
        HIGHEST,
        sub(1, 1, cob_id, U32),
        sub(2, 2, "Transmission type", U8),
        sub(3, 3, "Inhibit time", U16),
        sub(4, 4, "Compatibility entry", U8),
        sub(5, 5, "Event-timer", U16),
        sub(6, 6, "SYNC start value", U8),
    ]
}

const PDO_COMM_RX: &[SubDescription] = &pdo_comm("COB-ID used by RPDO");
const PDO_COMM_TX: &[SubDescription] = &pdo_comm("COB-ID used by TPDO");

const PDO_MAPPING: &[SubDescription] = &[
    sub(0, 0, "Number of mapped application objects in PDO", U8),
    sub(1, 64, "Application object", U32),
];

/// The CiA 301 communication objects of the device core
/// ([`CommObjects`](crate::device::CommObjects): 1000h, 1001h, 1003h, 1005h-1008h,
/// 100Ch, 100Dh, 1010h and 1011h (feature `store`), 1012h, 1016h-1019h, 1200h) and the PDO communication and mapping parameters
/// (1400h-1BFFh), with the object and sub-object names of CiA 301
/// ("CANopen application layer and communication profile", section 7.5.2
/// "Object dictionary entries": 7.5.2.1 device type to 7.5.2.38 TPDO
/// mapping parameter) and their data types. A run of PDO parameters is
/// named with its number from 1 ("RPDO communication parameter 1" is
/// 1400h, the crate's `PdoNumber::P0`).
pub const COMM_OBJECT_DESCRIPTIONS: &[ObjectDescription] = &[
    ObjectDescription::var(DEVICE_TYPE, "Device type", U32),
    ObjectDescription::var(ERROR_REGISTER, "Error register", U8),
    ObjectDescription::with_subs(
        PRE_DEFINED_ERROR_FIELD,
        PRE_DEFINED_ERROR_FIELD,
        "Pre-defined error field",
        ObjectType::Array,
        &[
            sub(0, 0, "Number of errors", U8),
            sub(1, 254, "Standard error field", U32),
        ],
    ),
    ObjectDescription::var(COB_ID_SYNC, "COB-ID SYNC message", U32),
    ObjectDescription::var(
        COMMUNICATION_CYCLE_PERIOD,
        "Communication cycle period",
        U32,
    ),
    ObjectDescription::var(SYNCHRONOUS_WINDOW_LENGTH, "Synchronous window length", U32),
    ObjectDescription::var(
        MANUFACTURER_DEVICE_NAME,
        "Manufacturer device name",
        DataType::VisibleString,
    ),
    ObjectDescription::var(GUARD_TIME, "Guard time", U16),
    ObjectDescription::var(LIFE_TIME_FACTOR, "Life time factor", U8),
    ObjectDescription::with_subs(
        STORE_PARAMETERS,
        STORE_PARAMETERS,
        "Store parameters",
        ObjectType::Array,
        &[
            HIGHEST,
            sub(1, 1, "Save all parameters", U32),
            sub(2, 2, "Save communication parameters", U32),
            sub(3, 3, "Save application parameters", U32),
        ],
    ),
    ObjectDescription::with_subs(
        RESTORE_DEFAULT_PARAMETERS,
        RESTORE_DEFAULT_PARAMETERS,
        "Restore default parameters",
        ObjectType::Array,
        &[
            HIGHEST,
            sub(1, 1, "Restore all default parameters", U32),
            sub(2, 2, "Restore communication default parameters", U32),
            sub(3, 3, "Restore application default parameters", U32),
        ],
    ),
    ObjectDescription::var(COB_ID_TIME, "COB-ID time stamp object", U32),
    ObjectDescription::with_subs(
        CONSUMER_HEARTBEAT_TIME,
        CONSUMER_HEARTBEAT_TIME,
        "Consumer heartbeat time",
        ObjectType::Array,
        &[HIGHEST, sub(1, 127, "Consumer heartbeat time", U32)],
    ),
    ObjectDescription::var(PRODUCER_HEARTBEAT_TIME, "Producer heartbeat time", U16),
    ObjectDescription::with_subs(
        IDENTITY,
        IDENTITY,
        "Identity object",
        ObjectType::Record,
        &[
            HIGHEST,
            sub(1, 1, "Vendor-ID", U32),
            sub(2, 2, "Product code", U32),
            sub(3, 3, "Revision number", U32),
            sub(4, 4, "Serial number", U32),
        ],
    ),
    ObjectDescription::var(
        SYNCHRONOUS_COUNTER_OVERFLOW,
        "Synchronous counter overflow value",
        U8,
    ),
    ObjectDescription::with_subs(
        SDO_SERVER_PARAMETER,
        SDO_SERVER_PARAMETER,
        "SDO server parameter",
        ObjectType::Record,
        &[
            HIGHEST,
            sub(1, 1, "COB-ID client to server (rx)", U32),
            sub(2, 2, "COB-ID server to client (tx)", U32),
            sub(3, 3, "Node-ID of the SDO client", U8),
        ],
    ),
    ObjectDescription::with_subs(
        RPDO_COMMUNICATION,
        RPDO_COMMUNICATION_LAST,
        "RPDO communication parameter",
        ObjectType::Record,
        PDO_COMM_RX,
    ),
    ObjectDescription::with_subs(
        RPDO_MAPPING,
        RPDO_MAPPING_LAST,
        "RPDO mapping parameter",
        ObjectType::Record,
        PDO_MAPPING,
    ),
    ObjectDescription::with_subs(
        TPDO_COMMUNICATION,
        TPDO_COMMUNICATION_LAST,
        "TPDO communication parameter",
        ObjectType::Record,
        PDO_COMM_TX,
    ),
    ObjectDescription::with_subs(
        TPDO_MAPPING,
        TPDO_MAPPING_LAST,
        "TPDO mapping parameter",
        ObjectType::Record,
        PDO_MAPPING,
    ),
];
