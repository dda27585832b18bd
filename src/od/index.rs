//! CiA 301 object indexes: the communication profile area (1000h-1FFFh)
//! that every device profile builds on, in one place. Profiles re-export
//! what they need from here rather than defining their own copies.
//!
//! PDOs count from 0 ([`PdoNumber`](crate::PdoNumber)): RPDO n has its
//! communication parameters at [`RPDO_COMMUNICATION`] + n and its mapping at
//! [`RPDO_MAPPING`] + n; TPDO n at [`TPDO_COMMUNICATION`] + n and
//! [`TPDO_MAPPING`] + n.

/// 1000h device type, U32 const (CiA 301, communication profile area): bits
/// 0-15 the device profile number, bits 16-31 profile-specific additional
/// information.
pub const DEVICE_TYPE: u16 = 0x1000;
/// 1001h error register, U8 ro (CiA 301): bit 0 generic error, 1 current,
/// 2 voltage, 3 temperature, 4 communication, 5 device-profile specific,
/// 7 manufacturer specific. It is also byte 2 of every EMCY frame.
pub const ERROR_REGISTER: u16 = 0x1001;
/// 1003h pre-defined error field, ARRAY of U32 (CiA 301): sub 0 the number
/// of errors recorded, sub 1 the newest; each entry has the emergency error
/// code in its low word and manufacturer-specific information in its high
/// word. Writing 0 to sub 0 clears the list.
pub const PRE_DEFINED_ERROR_FIELD: u16 = 0x1003;
/// 1005h COB-ID SYNC, U32 rw (CiA 301): bit 30 set makes the device the
/// SYNC producer, bits 0-10 the identifier (default 080h).
pub const COB_ID_SYNC: u16 = 0x1005;
/// 1006h communication cycle period, U32 rw, in µs (CiA 301): the SYNC
/// interval; 0 disables SYNC production.
pub const COMMUNICATION_CYCLE_PERIOD: u16 = 0x1006;
/// 1007h synchronous window length, U32 rw, in µs (CiA 301): synchronous
/// PDOs are sent and received within this time after the SYNC; 0: no window.
pub const SYNCHRONOUS_WINDOW_LENGTH: u16 = 0x1007;
/// 1008h manufacturer device name, VISIBLE_STRING const (CiA 301).
pub const MANUFACTURER_DEVICE_NAME: u16 = 0x1008;
/// 1009h manufacturer hardware version, VISIBLE_STRING const (CiA 301).
pub const MANUFACTURER_HARDWARE_VERSION: u16 = 0x1009;
/// 100Ah manufacturer software version, VISIBLE_STRING const (CiA 301).
pub const MANUFACTURER_SOFTWARE_VERSION: u16 = 0x100A;
/// 100Ch guard time, U16 rw, in ms (CiA 301): the node-guarding period the
/// slave expects; with 100Dh it gives the node life time.
pub const GUARD_TIME: u16 = 0x100C;
/// 100Dh life time factor, U8 rw (CiA 301): node life time = guard time x
/// life time factor; 0 disables life guarding.
pub const LIFE_TIME_FACTOR: u16 = 0x100D;
/// 1010h store parameters, ARRAY of U32 (CiA 301): writing the signature
/// "save" (6576_6173h) to a sub-index stores that group of parameters.
pub const STORE_PARAMETERS: u16 = 0x1010;
/// 1011h restore default parameters, ARRAY of U32 (CiA 301): writing the
/// signature "load" (6461_6F6Ch) restores the defaults at the next reset.
pub const RESTORE_DEFAULT_PARAMETERS: u16 = 0x1011;
/// 1012h COB-ID time stamp object, U32 rw (CiA 301): the TIME identifier
/// (default 100h), bit 31 consumer, bit 30 producer.
pub const COB_ID_TIME: u16 = 0x1012;
/// 1014h COB-ID EMCY, U32 (CiA 301): default 080h + node id, bit 31 set
/// when the device produces no EMCY.
pub const COB_ID_EMCY: u16 = 0x1014;
/// 1015h inhibit time EMCY, U16 rw, in multiples of 100 µs (CiA 301).
pub const INHIBIT_TIME_EMCY: u16 = 0x1015;
/// 1016h consumer heartbeat time, ARRAY of U32 rw (CiA 301): each entry has
/// the monitored node id in bits 16-23 and the timeout in ms in bits 0-15;
/// node 0 or time 0 disables the entry.
pub const CONSUMER_HEARTBEAT_TIME: u16 = 0x1016;
/// 1017h producer heartbeat time, U16 rw, in ms (CiA 301): 0 disables the
/// heartbeat.
pub const PRODUCER_HEARTBEAT_TIME: u16 = 0x1017;
/// 1018h identity object, RECORD of U32 ro (CiA 301): sub 1 vendor id,
/// sub 2 product code, sub 3 revision number, sub 4 serial number.
pub const IDENTITY: u16 = 0x1018;
/// 1019h synchronous counter overflow value, U8 rw (CiA 301): 0 SYNC
/// without counter, 2..=240 the highest counter value, 1 and 241..=255
/// reserved; written only while 1006h is 0.
pub const SYNCHRONOUS_COUNTER_OVERFLOW: u16 = 0x1019;
/// 1029h error behaviour, ARRAY of U8 (CiA 301): the NMT state a device
/// enters on a communication error.
pub const ERROR_BEHAVIOUR: u16 = 0x1029;
/// 1200h first SDO server parameter, RECORD of U32 (CiA 301): sub 1 the
/// COB-ID client to server (default 600h + node id), sub 2 server to client
/// (default 580h + node id). The next servers follow at 1201h-127Fh.
pub const SDO_SERVER_PARAMETER: u16 = 0x1200;
/// 1280h first SDO client parameter, RECORD (CiA 301): sub 1 the COB-ID
/// client to server, sub 2 server to client, sub 3 the server's node id.
pub const SDO_CLIENT_PARAMETER: u16 = 0x1280;
/// 1400h communication parameter of RPDO 0, RECORD (CiA 301); RPDO n is at
/// 1400h + n (up to 15FFh): sub 1 COB-ID, sub 2 transmission type, sub 5
/// event timer.
pub const RPDO_COMMUNICATION: u16 = 0x1400;
/// 1600h mapping parameter of RPDO 0, RECORD of U32 (CiA 301); RPDO n is at
/// 1600h + n (up to 17FFh): sub 0 the number of entries, subs 1-64 the
/// entries `index << 16 | sub << 8 | bits`.
pub const RPDO_MAPPING: u16 = 0x1600;
/// 1800h communication parameter of TPDO 0, RECORD (CiA 301); TPDO n is at
/// 1800h + n (up to 19FFh): sub 1 COB-ID, sub 2 transmission type, sub 3
/// inhibit time, sub 5 event timer.
pub const TPDO_COMMUNICATION: u16 = 0x1800;
/// 1A00h mapping parameter of TPDO 0, RECORD of U32 (CiA 301); TPDO n is at
/// 1A00h + n (up to 1BFFh), laid out as [`RPDO_MAPPING`].
pub const TPDO_MAPPING: u16 = 0x1A00;

/// How many PDOs of each direction the index ranges above have room for
/// (CiA 301, 7.5.2.35-7.5.2.38: 512 each, numbered 1-512 in the standard,
/// 0-511 here).
pub const PDO_SLOTS: u16 = 512;
/// The last RPDO communication parameter (15FFh).
pub const RPDO_COMMUNICATION_LAST: u16 = RPDO_COMMUNICATION + (PDO_SLOTS - 1);
/// The last RPDO mapping parameter (17FFh).
pub const RPDO_MAPPING_LAST: u16 = RPDO_MAPPING + (PDO_SLOTS - 1);
/// The last TPDO communication parameter (19FFh).
pub const TPDO_COMMUNICATION_LAST: u16 = TPDO_COMMUNICATION + (PDO_SLOTS - 1);
/// The last TPDO mapping parameter (1BFFh).
pub const TPDO_MAPPING_LAST: u16 = TPDO_MAPPING + (PDO_SLOTS - 1);
/// The first index of the communication profile area (CiA 301, 7.4.1
/// "Object dictionary", table 42: 1000h-1FFFh).
pub const COMMUNICATION_AREA_FIRST: u16 = DEVICE_TYPE;
/// The last index of the communication profile area (1FFFh).
pub const COMMUNICATION_AREA_LAST: u16 = 0x1FFF;

/// 1F22h "concise DCF", per node (CiA 302-3 "Configuration and program
/// download", section 4).
pub const CONCISE_DCF: u16 = 0x1F22;
/// 1F52h "verify application software": sub 1 date, sub 2 time (CiA 302-3
/// section 4).
pub const VERIFY_APPLICATION_SOFTWARE: u16 = 0x1F52;
/// 1F53h "expected application software date", per node (CiA 302-3).
pub const EXPECTED_APPLICATION_SW_DATE: u16 = 0x1F53;
/// 1F54h "expected application software time", per node (CiA 302-3).
pub const EXPECTED_APPLICATION_SW_TIME: u16 = 0x1F54;
/// 1F55h "expected software identification", per node (CiA 302-3).
pub const EXPECTED_SOFTWARE_IDENTIFICATION: u16 = 0x1F55;
/// 1F80h "NMT start-up" (CiA 302-2 "Network management", section 4.2).
pub const NMT_STARTUP: u16 = 0x1F80;
/// 1F81h "NMT slave assignment", per node (CiA 302-2 section 4.2).
pub const NMT_SLAVE_ASSIGNMENT: u16 = 0x1F81;
/// 1F82h "request NMT", per node, 128 all nodes (CiA 302-2 section 4.2).
pub const REQUEST_NMT: u16 = 0x1F82;
/// 1F83h "request node guarding", per node (CiA 302-2 section 4.2).
pub const REQUEST_NODE_GUARDING: u16 = 0x1F83;
/// 1F84h "device type identification", per node (CiA 302-2 section 4.2);
/// 1F85h-1F88h follow it: vendor, product code, revision, serial number.
pub const DEVICE_TYPE_IDENTIFICATION: u16 = 0x1F84;
/// 1F85h "vendor identification", per node (CiA 302-2 section 4.2).
pub const VENDOR_IDENTIFICATION: u16 = DEVICE_TYPE_IDENTIFICATION + 1;
/// 1F86h "product code", per node (CiA 302-2 section 4.2).
pub const PRODUCT_CODE_IDENTIFICATION: u16 = DEVICE_TYPE_IDENTIFICATION + 2;
/// 1F87h "revision number", per node (CiA 302-2 section 4.2).
pub const REVISION_NUMBER_IDENTIFICATION: u16 = DEVICE_TYPE_IDENTIFICATION + 3;
/// 1F88h "serial number", per node (CiA 302-2 section 4.2).
pub const SERIAL_NUMBER_IDENTIFICATION: u16 = DEVICE_TYPE_IDENTIFICATION + 4;
/// 1F89h "boot time" (CiA 302-2 section 4.2).
pub const BOOT_TIME: u16 = 0x1F89;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cia301_indexes() {
        let rows: [(u16, u16); 50] = [
            (DEVICE_TYPE, 0x1000),
            (ERROR_REGISTER, 0x1001),
            (PRE_DEFINED_ERROR_FIELD, 0x1003),
            (COB_ID_SYNC, 0x1005),
            (COMMUNICATION_CYCLE_PERIOD, 0x1006),
            (SYNCHRONOUS_WINDOW_LENGTH, 0x1007),
            (MANUFACTURER_DEVICE_NAME, 0x1008),
            (MANUFACTURER_HARDWARE_VERSION, 0x1009),
            (MANUFACTURER_SOFTWARE_VERSION, 0x100A),
            (GUARD_TIME, 0x100C),
            (LIFE_TIME_FACTOR, 0x100D),
            (STORE_PARAMETERS, 0x1010),
            (RESTORE_DEFAULT_PARAMETERS, 0x1011),
            (COB_ID_TIME, 0x1012),
            (COB_ID_EMCY, 0x1014),
            (INHIBIT_TIME_EMCY, 0x1015),
            (CONSUMER_HEARTBEAT_TIME, 0x1016),
            (PRODUCER_HEARTBEAT_TIME, 0x1017),
            (IDENTITY, 0x1018),
            (SYNCHRONOUS_COUNTER_OVERFLOW, 0x1019),
            (ERROR_BEHAVIOUR, 0x1029),
            (SDO_SERVER_PARAMETER, 0x1200),
            (SDO_CLIENT_PARAMETER, 0x1280),
            (RPDO_COMMUNICATION, 0x1400),
            (RPDO_MAPPING, 0x1600),
            (TPDO_COMMUNICATION, 0x1800),
            (TPDO_MAPPING, 0x1A00),
            (RPDO_MAPPING - RPDO_COMMUNICATION, 0x200),
            (TPDO_MAPPING - TPDO_COMMUNICATION, 0x200),
            (RPDO_COMMUNICATION_LAST, 0x15FF),
            (RPDO_MAPPING_LAST, 0x17FF),
            (TPDO_COMMUNICATION_LAST, 0x19FF),
            (TPDO_MAPPING_LAST, 0x1BFF),
            (COMMUNICATION_AREA_FIRST, 0x1000),
            (COMMUNICATION_AREA_LAST, 0x1FFF),
            (CONCISE_DCF, 0x1F22),
            (VERIFY_APPLICATION_SOFTWARE, 0x1F52),
            (EXPECTED_APPLICATION_SW_DATE, 0x1F53),
            (EXPECTED_APPLICATION_SW_TIME, 0x1F54),
            (EXPECTED_SOFTWARE_IDENTIFICATION, 0x1F55),
            (NMT_STARTUP, 0x1F80),
            (NMT_SLAVE_ASSIGNMENT, 0x1F81),
            (REQUEST_NMT, 0x1F82),
            (REQUEST_NODE_GUARDING, 0x1F83),
            (DEVICE_TYPE_IDENTIFICATION, 0x1F84),
            (VENDOR_IDENTIFICATION, 0x1F85),
            (PRODUCT_CODE_IDENTIFICATION, 0x1F86),
            (REVISION_NUMBER_IDENTIFICATION, 0x1F87),
            (SERIAL_NUMBER_IDENTIFICATION, 0x1F88),
            (BOOT_TIME, 0x1F89),
        ];
        for (got, want) in rows {
            assert_eq!(got, want, "{want:04X}h");
        }
    }
}
