//! The communication objects every device of the core has (CiA 301,
//! 1000h-1FFFh apart from the PDO objects), and the dictionary that layers
//! them over the profile's application objects
//! (the table is in the [device core docs](crate::device)).
//!
//! Objects the table does not name are passed to the application's
//! dictionary, which may add communication objects of its own.

use crate::abort::AbortCode;
use crate::cob_id::{NodeId, SDO_RX_BASE, SDO_TX_BASE};
use crate::emcy::{Emergency, ErrorFieldEntry, ErrorRegister};
#[cfg(feature = "heartbeat-consumer")]
use crate::nmt::heartbeat::ConsumerEntry;
#[cfg(feature = "heartbeat-consumer")]
use crate::od::index::CONSUMER_HEARTBEAT_TIME;
use crate::od::index::{
    COB_ID_SYNC, COB_ID_TIME, COMMUNICATION_CYCLE_PERIOD, DEVICE_TYPE, ERROR_REGISTER, GUARD_TIME,
    IDENTITY, LIFE_TIME_FACTOR, MANUFACTURER_DEVICE_NAME, PRE_DEFINED_ERROR_FIELD,
    PRODUCER_HEARTBEAT_TIME, SDO_SERVER_PARAMETER, SYNCHRONOUS_COUNTER_OVERFLOW,
    SYNCHRONOUS_WINDOW_LENGTH,
};
#[cfg(feature = "store")]
use crate::od::index::{RESTORE_DEFAULT_PARAMETERS, STORE_PARAMETERS};
use crate::od::{comm, Access, Address, ObjectDictionary, ObjectInfo, SizeRule, WriteBuffer};

/// The row of the communication table ([`comm::COMM_OBJECTS`]) for
/// `$index` sub `$sub` (0 if left out), found when the crate is built: an
/// object the device core serves without a row does not build.
macro_rules! row {
    ($index:expr) => {
        row!($index, 0)
    };
    ($index:expr, $sub:expr) => {
        const {
            match comm::find(Address::new($index, $sub)) {
                Some(row) => *row,
                None => panic!("every object the device core serves has a row in od::comm"),
            }
        }
    };
}

/// The access rights of an object (see [`row!`]).
macro_rules! access {
    ($($address:expr),+) => {
        const { row!($($address),+).access }
    };
}

/// The power-on value of an object (see [`row!`]).
macro_rules! default {
    ($($address:expr),+) => {
        const { row!($($address),+).default }
    };
}
use crate::sync::{valid_counter_overflow, SyncCobId};
use crate::time::TimeCobId;

/// Entries the error history (1003h) keeps.
pub const ERROR_HISTORY_LEN: usize = 10;
/// Heartbeat consumer entries (1016h sub-indexes) a device can have
/// (feature `heartbeat-consumer`).
#[cfg(feature = "heartbeat-consumer")]
pub const MAX_CONSUMERS: usize = 4;
/// 1010h's signature: "save" (73 61 76 65) read as a little-endian U32
/// (CiA 301 section 7.5.2.13).
#[cfg(feature = "store")]
pub const SAVE_SIGNATURE: u32 = 0x6576_6173;
/// 1011h's signature: "load" (6C 6F 61 64) read as a little-endian U32
/// (CiA 301 section 7.5.2.14).
#[cfg(feature = "store")]
pub const LOAD_SIGNATURE: u32 = 0x6461_6F6C;
/// The capability word of a group stored (or restored) on command.
#[cfg(feature = "store")]
pub const ON_COMMAND: u32 = 1;

/// 1018h identity object: sub 1-4 (CiA 301).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Identity {
    /// Sub 1: vendor-ID (assigned by CiA).
    pub vendor_id: u32,
    /// Sub 2: product code.
    pub product_code: u32,
    /// Sub 3: revision number.
    pub revision_number: u32,
    /// Sub 4: serial number.
    pub serial_number: u32,
}

impl Identity {
    /// Value of sub 0, highest sub-index supported (the communication
    /// table's power-on value of 1018h sub 0).
    pub const HIGHEST_SUB_INDEX: u8 = default!(IDENTITY) as u8;

    /// All zero.
    pub const ZERO: Identity = Identity {
        vendor_id: 0,
        product_code: 0,
        revision_number: 0,
        serial_number: 0,
    };

    /// The value of sub-index `sub` (1..=4).
    #[must_use]
    pub const fn sub(&self, sub: u8) -> Option<u32> {
        match sub {
            1 => Some(self.vendor_id),
            2 => Some(self.product_code),
            3 => Some(self.revision_number),
            4 => Some(self.serial_number),
            _ => None,
        }
    }
}

/// How an emergency becomes a 1003h entry. CiA 301 puts the error code in
/// bits 0-15 and leaves bits 16-31 to the manufacturer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ErrorFieldFormat {
    /// Bits 16-31: manufacturer bytes 0-1 of the EMCY, little-endian.
    #[default]
    LittleEndianInfo,
    /// Bits 16-31: manufacturer bytes 0-1 of the EMCY with their bytes
    /// swapped (the Delta-Q IC Series charger's 1003h).
    SwappedInfo,
}

impl ErrorFieldFormat {
    /// The 1003h entry for `emcy`.
    #[must_use]
    pub const fn entry(self, emcy: &Emergency) -> ErrorFieldEntry {
        let [m0, m1, ..] = emcy.manufacturer;
        let info = u16::from_le_bytes([m0, m1]);
        ErrorFieldEntry {
            code: emcy.code,
            info: match self {
                ErrorFieldFormat::LittleEndianInfo => info,
                ErrorFieldFormat::SwappedInfo => info.swap_bytes(),
            },
        }
    }
}

/// The communication objects of the table in the [device core docs](crate::device).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CommObjects {
    node: NodeId,
    /// 1000h.
    pub device_type: u32,
    /// 1001h.
    pub error_register: ErrorRegister,
    history: [u32; ERROR_HISTORY_LEN],
    history_len: u8,
    /// 1008h.
    pub device_name: &'static str,
    /// 1016h (feature `heartbeat-consumer`).
    #[cfg(feature = "heartbeat-consumer")]
    consumers: [ConsumerEntry; MAX_CONSUMERS],
    #[cfg(feature = "heartbeat-consumer")]
    consumer_slots: u8,
    /// 1017h, ms.
    pub heartbeat_ms: u16,
    /// 1018h.
    pub identity: Identity,
    /// 1005h COB-ID SYNC.
    pub sync_cob_id: SyncCobId,
    /// 1006h communication cycle period, µs.
    pub cycle_period_us: u32,
    /// 1007h synchronous window length, µs.
    pub sync_window_us: u32,
    /// 100Ch guard time, ms.
    pub guard_time_ms: u16,
    /// 100Dh life time factor.
    pub life_time_factor: u8,
    /// 1012h COB-ID TIME.
    pub time_cob_id: TimeCobId,
    /// 1019h synchronous counter overflow value.
    pub sync_counter_overflow: u8,
    /// 1010h/1011h: bit 0 the communication group can be stored, bit 1 the
    /// application group (feature `store`).
    #[cfg(feature = "store")]
    storable: u8,
    pending: WriteBuffer,
}

impl CommObjects {
    /// The objects of node `node` with an empty history, no error, no
    /// consumer entries and the other values zero or empty.
    #[must_use]
    pub const fn new(node: NodeId) -> Self {
        CommObjects {
            node,
            device_type: 0,
            error_register: ErrorRegister::empty(),
            history: [0; ERROR_HISTORY_LEN],
            history_len: 0,
            device_name: "",
            #[cfg(feature = "heartbeat-consumer")]
            consumers: [ConsumerEntry::DISABLED; MAX_CONSUMERS],
            #[cfg(feature = "heartbeat-consumer")]
            consumer_slots: 0,
            heartbeat_ms: 0,
            identity: Identity::ZERO,
            sync_cob_id: SyncCobId::DEFAULT,
            cycle_period_us: 0,
            sync_window_us: 0,
            guard_time_ms: 0,
            life_time_factor: 0,
            time_cob_id: TimeCobId::DEFAULT,
            sync_counter_overflow: 0,
            #[cfg(feature = "store")]
            storable: 0,
            pending: WriteBuffer::new(),
        }
    }

    /// Back to the objects of node `node` ([`new`](Self::new)) but for
    /// 1000h device type, 1008h device name and 1018h identity, which
    /// keep their values: `const` / `ro` objects nothing on the bus
    /// changes, which a profile writes once, when its device is made
    /// ([`DeviceSetup::write_constants`](super::DeviceSetup::write_constants)),
    /// and every reset keeps.
    pub fn reset_keeping_constants(&mut self, node: NodeId) {
        let (device_type, device_name, identity) =
            (self.device_type, self.device_name, self.identity);
        *self = CommObjects::new(node);
        self.device_type = device_type;
        self.device_name = device_name;
        self.identity = identity;
    }

    /// The node id (1200h values).
    #[must_use]
    pub const fn node(&self) -> NodeId {
        self.node
    }

    /// Records an entry in 1003h: newest first, at most 10 (the oldest falls off).
    pub fn push_error(&mut self, entry: ErrorFieldEntry) {
        // The newest entry first, the others shifted down one (CiA 301,
        // 1003h: sub 1 is the newest error; the oldest falls off).
        let mut history = [0; ERROR_HISTORY_LEN];
        if let (Some((first, rest)), Some(kept)) = (
            history.split_first_mut(),
            self.history.get(..ERROR_HISTORY_LEN - 1),
        ) {
            *first = entry.to_u32();
            rest.copy_from_slice(kept);
        }
        self.history = history;
        self.history_len = (self.history_len + 1).min(ERROR_HISTORY_LEN as u8);
    }

    /// The error history (1003h sub 1..), newest first.
    #[must_use]
    pub fn errors(&self) -> &[u32] {
        // The `min`s (the lengths never exceed the arrays) let the
        // compiler drop the fallbacks.
        self.history
            .get(..usize::from(self.history_len).min(ERROR_HISTORY_LEN))
            .unwrap_or(&[])
    }

    /// Clears the error history (what writing 0 to 1003h sub 0 does).
    pub fn clear_errors(&mut self) {
        self.history = [0; ERROR_HISTORY_LEN];
        self.history_len = 0;
    }

    /// Sets the 1016h entries: sub 0 becomes `entries.len()` (at most
    /// [`MAX_CONSUMERS`]; extra entries are ignored). No entries: no 1016h.
    /// Feature `heartbeat-consumer` (without it there is no 1016h).
    #[cfg(feature = "heartbeat-consumer")]
    pub fn set_consumers(&mut self, entries: &[ConsumerEntry]) {
        self.consumers = [ConsumerEntry::default(); MAX_CONSUMERS];
        let mut n = 0u8;
        for (slot, e) in self.consumers.iter_mut().zip(entries) {
            *slot = *e;
            n += 1;
        }
        self.consumer_slots = n;
    }

    /// The 1016h entries (sub 1..=sub 0). Feature `heartbeat-consumer`.
    #[cfg(feature = "heartbeat-consumer")]
    #[must_use]
    pub fn consumers(&self) -> &[ConsumerEntry] {
        self.consumers
            .get(..usize::from(self.consumer_slots).min(MAX_CONSUMERS))
            .unwrap_or(&[])
    }

    /// Which groups 1010h/1011h store and restore (the device's storage;
    /// feature `store`).
    #[cfg(feature = "store")]
    pub(super) fn set_storable(&mut self, communication: bool, application: bool) {
        self.storable = u8::from(communication) | u8::from(application) << 1;
    }

    /// The capability word of 1010h/1011h sub `sub` (1 all, 2
    /// communication, 3 application): [`ON_COMMAND`]
    /// when the device stores that group on command, else 0.
    #[cfg(feature = "store")]
    #[must_use]
    pub const fn store_capability(&self, sub: u8) -> u32 {
        let group = match sub {
            1 => 0b11,
            2 => 0b01,
            3 => 0b10,
            _ => 0,
        };
        if self.storable & group != 0 {
            ON_COMMAND
        } else {
            0
        }
    }

    /// True if the index is one of these objects.
    #[must_use]
    pub const fn has_object(&self, index: u16) -> bool {
        match index {
            // The heartbeat consumer (feature `heartbeat-consumer`).
            #[cfg(feature = "heartbeat-consumer")]
            CONSUMER_HEARTBEAT_TIME => self.consumer_slots > 0,
            DEVICE_TYPE
            | ERROR_REGISTER
            | PRE_DEFINED_ERROR_FIELD
            | MANUFACTURER_DEVICE_NAME
            | PRODUCER_HEARTBEAT_TIME
            | IDENTITY
            | SDO_SERVER_PARAMETER
            | COB_ID_SYNC
            | SYNCHRONOUS_WINDOW_LENGTH
            | SYNCHRONOUS_COUNTER_OVERFLOW => true,
            // Store and restore (feature `store`).
            #[cfg(feature = "store")]
            STORE_PARAMETERS | RESTORE_DEFAULT_PARAMETERS => true,
            // The SYNC producer's period and TIME (feature `sync-time`).
            COMMUNICATION_CYCLE_PERIOD | COB_ID_TIME => cfg!(feature = "sync-time"),
            // Node guarding (feature `guarding`).
            GUARD_TIME | LIFE_TIME_FACTOR => cfg!(feature = "guarding"),
            _ => false,
        }
    }

    /// Access, length and value of every object: the one lookup
    /// [`info`](ObjectDictionary::info), [`read`](ObjectDictionary::read)
    /// and the writes share.
    fn entry(&self, index: u16, sub: u8) -> Result<Entry, AbortCode> {
        let node = u32::from(self.node.raw());
        // The single-value objects first, by index alone (one dense
        // switch), their one sub-index checked once.
        let single = match index {
            DEVICE_TYPE => Some((access!(DEVICE_TYPE), Value::u32(self.device_type))),
            ERROR_REGISTER => Some((
                access!(ERROR_REGISTER),
                Value::u8(self.error_register.bits()),
            )),
            MANUFACTURER_DEVICE_NAME => Some((access!(MANUFACTURER_DEVICE_NAME), Value::Name)),
            PRODUCER_HEARTBEAT_TIME => Some((
                access!(PRODUCER_HEARTBEAT_TIME),
                Value::u16(self.heartbeat_ms),
            )),
            COB_ID_SYNC => Some((access!(COB_ID_SYNC), Value::u32(self.sync_cob_id.raw()))),
            #[cfg(feature = "sync-time")]
            COMMUNICATION_CYCLE_PERIOD => Some((
                access!(COMMUNICATION_CYCLE_PERIOD),
                Value::u32(self.cycle_period_us),
            )),
            SYNCHRONOUS_WINDOW_LENGTH => Some((
                access!(SYNCHRONOUS_WINDOW_LENGTH),
                Value::u32(self.sync_window_us),
            )),
            #[cfg(feature = "guarding")]
            GUARD_TIME => Some((access!(GUARD_TIME), Value::u16(self.guard_time_ms))),
            #[cfg(feature = "guarding")]
            LIFE_TIME_FACTOR => Some((access!(LIFE_TIME_FACTOR), Value::u8(self.life_time_factor))),
            #[cfg(feature = "sync-time")]
            COB_ID_TIME => Some((access!(COB_ID_TIME), Value::u32(self.time_cob_id.raw()))),
            SYNCHRONOUS_COUNTER_OVERFLOW => Some((
                access!(SYNCHRONOUS_COUNTER_OVERFLOW),
                Value::u8(self.sync_counter_overflow),
            )),
            _ => None,
        };
        let (access, value) = match (single, index, sub) {
            (Some(object), _, 0) => object,
            (Some(_), _, _) => return Err(AbortCode::SubIndexDoesNotExist),
            (None, PRE_DEFINED_ERROR_FIELD, 0) => (
                access!(PRE_DEFINED_ERROR_FIELD),
                Value::u8(self.history_len),
            ),
            (None, PRE_DEFINED_ERROR_FIELD, 1..=10) => {
                let access = access!(PRE_DEFINED_ERROR_FIELD, 1);
                match self.errors().get(usize::from(sub) - 1) {
                    Some(e) => (access, Value::u32(*e)),
                    None => (access, Value::NoData),
                }
            }
            #[cfg(feature = "heartbeat-consumer")]
            (None, CONSUMER_HEARTBEAT_TIME, 0) if self.consumer_slots > 0 => (
                access!(CONSUMER_HEARTBEAT_TIME),
                Value::u8(self.consumer_slots),
            ),
            #[cfg(feature = "heartbeat-consumer")]
            (None, CONSUMER_HEARTBEAT_TIME, s) if s > 0 => {
                match self.consumers().get(usize::from(s) - 1) {
                    Some(e) => (access!(CONSUMER_HEARTBEAT_TIME, 1), Value::u32(e.to_u32())),
                    None => return Err(AbortCode::SubIndexDoesNotExist),
                }
            }
            // CiA 301 sections 7.5.2.13/7.5.2.14: sub 0 the highest sub,
            // subs 1-3 the capability words.
            #[cfg(feature = "store")]
            (None, STORE_PARAMETERS, 0) => (
                access!(STORE_PARAMETERS),
                Value::u8(default!(STORE_PARAMETERS) as u8),
            ),
            #[cfg(feature = "store")]
            (None, RESTORE_DEFAULT_PARAMETERS, 0) => (
                access!(RESTORE_DEFAULT_PARAMETERS),
                Value::u8(default!(RESTORE_DEFAULT_PARAMETERS) as u8),
            ),
            #[cfg(feature = "store")]
            (None, STORE_PARAMETERS, 1..=3) => (
                access!(STORE_PARAMETERS, 1),
                Value::u32(self.store_capability(sub)),
            ),
            #[cfg(feature = "store")]
            (None, RESTORE_DEFAULT_PARAMETERS, 1..=3) => (
                access!(RESTORE_DEFAULT_PARAMETERS, 1),
                Value::u32(self.store_capability(sub)),
            ),
            (None, IDENTITY, 0) => (access!(IDENTITY), Value::u8(Identity::HIGHEST_SUB_INDEX)),
            (None, IDENTITY, s) => match self.identity.sub(s) {
                Some(v) => (access!(IDENTITY, 1), Value::u32(v)),
                None => return Err(AbortCode::SubIndexDoesNotExist),
            },
            (None, SDO_SERVER_PARAMETER, 0) => (
                access!(SDO_SERVER_PARAMETER),
                Value::u8(default!(SDO_SERVER_PARAMETER) as u8),
            ),
            (None, SDO_SERVER_PARAMETER, 1) => (
                access!(SDO_SERVER_PARAMETER, 1),
                Value::u32(u32::from(SDO_RX_BASE) + node),
            ),
            (None, SDO_SERVER_PARAMETER, 2) => (
                access!(SDO_SERVER_PARAMETER, 2),
                Value::u32(u32::from(SDO_TX_BASE) + node),
            ),
            (None, i, _) if self.has_object(i) => return Err(AbortCode::SubIndexDoesNotExist),
            _ => return Err(AbortCode::ObjectDoesNotExist),
        };
        let len = match value {
            Value::Word(_, len) => usize::from(len),
            Value::Name => self.device_name.len(),
            Value::NoData => 4,
        };
        Ok(Entry { access, len, value })
    }

    /// Applies a complete, length-checked write of `word` (the value's
    /// little-endian bytes, its length the object's) to a writable
    /// sub-object (as [`entry`](Self::entry) found it: each writable
    /// object has one writable sub-index, 0, but 1016h, whose sub-index
    /// `sub` names its entry), so the index alone picks the rule.
    fn apply(&mut self, index: u16, sub: u8, word: u32) -> Result<(), AbortCode> {
        // Only 1016h's entries (and 1010h/1011h's groups) are told apart
        // by their sub-index.
        #[cfg(not(any(feature = "heartbeat-consumer", feature = "store")))]
        let _ = sub;
        match index {
            PRE_DEFINED_ERROR_FIELD if word == 0 => self.clear_errors(),
            PRE_DEFINED_ERROR_FIELD => return Err(AbortCode::InvalidValue),
            #[cfg(feature = "heartbeat-consumer")]
            CONSUMER_HEARTBEAT_TIME => {
                let entry = ConsumerEntry::from_u32(word);
                let slot = usize::from(sub).wrapping_sub(1);
                let duplicate = entry.is_enabled()
                    && self
                        .consumers()
                        .iter()
                        .enumerate()
                        .any(|(i, e)| i != slot && e.is_enabled() && e.node == entry.node);
                if duplicate {
                    return Err(AbortCode::GeneralParameterIncompatibility);
                }
                match self.consumers.get_mut(slot) {
                    Some(e) if slot < usize::from(self.consumer_slots) => *e = entry,
                    _ => return Err(AbortCode::SubIndexDoesNotExist),
                }
            }
            // CiA 301 sections 7.5.2.13/7.5.2.14: only the signature is
            // accepted, for a group the device stores; the device core
            // stores or erases it (DeviceEvent::ObjectWritten's path).
            #[cfg(feature = "store")]
            STORE_PARAMETERS | RESTORE_DEFAULT_PARAMETERS => {
                let signature = if index == STORE_PARAMETERS {
                    SAVE_SIGNATURE
                } else {
                    LOAD_SIGNATURE
                };
                if word != signature || self.store_capability(sub) == 0 {
                    return Err(AbortCode::DataCannotBeStored);
                }
            }
            PRODUCER_HEARTBEAT_TIME => self.heartbeat_ms = word as u16,
            COB_ID_SYNC => {
                let new = SyncCobId::from_raw(word);
                // CiA 301 section 7.5.2, object 1005h: the identifier may
                // not change while the device generates SYNC, and it must
                // be a valid one.
                // Without the SYNC producer (feature `sync-time`) the
                // device cannot generate SYNC: the generate bit is refused
                // (which refuses a move while generating too).
                let refused = if cfg!(feature = "sync-time") {
                    let moved = new.raw() & 0x3FFF_FFFF != self.sync_cob_id.raw() & 0x3FFF_FFFF;
                    moved && self.sync_cob_id.generates() && new.generates()
                } else {
                    new.generates()
                };
                if new.id().is_none() || refused {
                    return Err(AbortCode::InvalidValue);
                }
                self.sync_cob_id = new;
            }
            #[cfg(feature = "sync-time")]
            COMMUNICATION_CYCLE_PERIOD => self.cycle_period_us = word,
            SYNCHRONOUS_WINDOW_LENGTH => self.sync_window_us = word,
            #[cfg(feature = "guarding")]
            GUARD_TIME => self.guard_time_ms = word as u16,
            #[cfg(feature = "guarding")]
            LIFE_TIME_FACTOR => self.life_time_factor = word as u8,
            #[cfg(feature = "sync-time")]
            COB_ID_TIME => {
                let new = TimeCobId::from_raw(word);
                if new.id().is_none() {
                    return Err(AbortCode::InvalidValue);
                }
                self.time_cob_id = new;
            }
            // CiA 301 section 7.5.2, object 1019h: written only while
            // 1006h is 0; 1 and 241..=255 are reserved.
            SYNCHRONOUS_COUNTER_OVERFLOW if self.cycle_period_us != 0 => {
                return Err(AbortCode::DataCannotBeStoredDeviceState)
            }
            SYNCHRONOUS_COUNTER_OVERFLOW if valid_counter_overflow(word as u8) => {
                self.sync_counter_overflow = word as u8;
            }
            SYNCHRONOUS_COUNTER_OVERFLOW => return Err(AbortCode::InvalidValue),
            _ => return Err(AbortCode::WriteOfReadOnlyObject),
        }
        Ok(())
    }
}

/// One sub-object as [`CommObjects::entry`] finds it.
#[derive(Debug, Clone, Copy)]
struct Entry {
    access: Access,
    /// Length of the value in bytes.
    len: usize,
    value: Value,
}

/// A value of up to 4 bytes (a little-endian word and its length), an
/// error-history entry beyond the history (4 bytes long, read as 08000024h
/// "no data available"), or the device name (1008h).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Value {
    Word(u32, u8),
    NoData,
    Name,
}

impl Value {
    const fn u8(v: u8) -> Self {
        Value::Word(v as u32, 1)
    }

    const fn u16(v: u16) -> Self {
        Value::Word(v as u32, 2)
    }

    const fn u32(v: u32) -> Self {
        Value::Word(v, 4)
    }
}

impl ObjectDictionary for CommObjects {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        let e = self.entry(index, sub)?;
        Ok(ObjectInfo {
            access: e.access,
            len: e.len,
            size: match e.value {
                Value::Name => SizeRule::Variable { max: 0 },
                _ => SizeRule::Fixed(e.len),
            },
            pdo_mappable: false,
        })
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let bytes;
        let src: &[u8] = match self.entry(index, sub)?.value {
            Value::Word(word, len) => {
                bytes = word.to_le_bytes();
                bytes.get(..usize::from(len)).unwrap_or(&bytes)
            }
            Value::NoData => return Err(AbortCode::NoDataAvailable),
            Value::Name => self.device_name.as_bytes(),
        };
        Ok(crate::od::read_at(src, offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        if !self.entry(index, sub)?.access.is_writable() {
            self.pending.clear();
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        self.pending.write(index, sub, offset, data)
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let e = self.pending.unless_refused(self.entry(index, sub))?;
        let word = self
            .pending
            .downloaded_value(e.access, e.len, index, sub, len)?;
        self.apply(index, sub, word)
    }

    fn abort_write(&mut self, _: u16, _: u8) {
        self.pending.clear();
    }
}

/// A device's dictionary below the PDO objects: the [`CommObjects`], then
/// the application's objects `A` for every index they do not have.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceObjects<A> {
    /// The communication objects.
    pub comm: CommObjects,
    /// The application (profile) objects.
    pub app: A,
}

impl<A: ObjectDictionary> ObjectDictionary for DeviceObjects<A> {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        if self.comm.has_object(index) {
            self.comm.info(index, sub)
        } else {
            self.app.info(index, sub)
        }
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        if self.comm.has_object(index) {
            self.comm.read(index, sub, offset, buf)
        } else {
            self.app.read(index, sub, offset, buf)
        }
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        if self.comm.has_object(index) {
            self.comm.write(index, sub, offset, data)
        } else {
            self.app.write(index, sub, offset, data)
        }
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        if self.comm.has_object(index) {
            self.comm.finish_write(index, sub, len)
        } else {
            self.app.finish_write(index, sub, len)
        }
    }

    fn abort_write(&mut self, index: u16, sub: u8) {
        if self.comm.has_object(index) {
            self.comm.abort_write(index, sub);
        } else {
            self.app.abort_write(index, sub);
        }
    }
}

#[cfg(test)]
#[path = "objects_tests.rs"]
mod tests;
