//! Store parameters (1010h) and restore default parameters (1011h), CiA 301
//! "CANopen application layer and communication profile" sections
//! 7.5.2.13 and 7.5.2.14, on a [`ParameterStorage`] the application
//! implements (feature `store`).
//!
//! # The objects
//!
//! Both are ARRAYs of U32 with sub 0 = 3 (const): sub 1 all parameters,
//! sub 2 the communication parameters (1000h-1FFFh), sub 3 the application
//! parameters (2000h-9FFFh: the manufacturer and the profile area). Reading
//! a sub gives its capability word: bit 0 set when the device stores (1010h)
//! or restores (1011h) that group on command; bit 1, storing on its own, is
//! never set. A device without a storage reads 0 everywhere.
//!
//! - Writing the signature "save" (65766173h, the bytes 73 61 76 65) to 1010h
//!   sub n stores group n at once; "load" (64616F6Ch, 6C 6F 61 64) to 1011h
//!   sub n erases its stored record, so the defaults come back at the next
//!   reset that restores the group: reset node for all of them, reset
//!   communication for the communication parameters (CiA 301 section
//!   7.5.2.14).
//! - Any other value, or a sub whose capability is 0 (no storage; sub 3 of a
//!   dictionary whose parameters cannot be stored): 08000020h "data cannot
//!   be transferred or stored". A sub above 3: 06090011h.
//! - A storage that fails: 06060000h "access failed due to a hardware
//!   error" (and [`StorageEvent::Failed`]).
//!
//! # What is stored
//!
//! The communication group is every writable communication object the core
//! holds: 1005h, 1006h, 1007h, 100Ch, 100Dh, 1012h, 1016h's entries, 1017h,
//! 1019h and the PDO configuration (1400h-1A03h). The application group is
//! the application dictionary's parameters, what reset node restores of it
//! ([`PowerOnValues::parameter_bytes`](super::PowerOnValues::parameter_bytes)). Both are loaded at
//! [`Device::boot`] and at the reset that restores them, over the power-on
//! values; a record that is corrupt, of another format or of another
//! dictionary is ignored ([`StorageEvent::Ignored`]) and the power-on values
//! stay. The LSS slave's store configuration (CiA 305) stores its pending
//! node-ID and bit timing as a third group, loaded at [`Device::boot`].
//!
//! # The record (format 1)
//!
//! | bytes | field |
//! |---|---|
//! | 0-1 | magic "CO" (43h 4Fh) |
//! | 2 | format version, 1 |
//! | 3 | group: 1 communication, 2 application, 3 LSS |
//! | 4-7 | layout, U32: communication `T` + 256 × `R`; application the dictionary's [`PowerOnValues::parameter_layout`](super::PowerOnValues::parameter_layout); LSS 0 |
//! | 8-9 | payload length n, U16 |
//! | 10..10+n | payload |
//! | 10+n..12+n | CRC-16 (the SDO block transfer's, CiA 301 section 7.2.4.3.16) of bytes 0..10+n, U16 |
//!
//! All little-endian. The communication payload: 1017h U16, 100Ch U16,
//! 100Dh U8, 1005h U32, 1006h U32, 1007h U32, 1012h U32, 1019h U8, the number
//! of 1016h entries U8 and 4 entries U32; then per PDO, the RPDOs 1..R and
//! the TPDOs 1..T: present U8 (0 or 1), COB-ID U32, transmission type U8,
//! inhibit time U16, sub 4 U8, event timer U16, mapping count U8 and 8
//! mapping entries U32. The application payload: the parameters' bytes. The
//! LSS payload: node-ID U8 (255: none), bit timing present U8, table U8,
//! index U8.
//!
//! [`Device::boot`]: super::Device::boot

use super::objects::CommObjects;
// The signatures and the capability word of 1010h and 1011h, defined with
// the objects that check them.
pub use super::objects::{LOAD_SIGNATURE, ON_COMMAND, SAVE_SIGNATURE};
#[cfg(feature = "lss")]
use crate::cob_id::NodeId;
use crate::cob_id::PdoNumber;
use crate::pdo::{
    MappingEntry, PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoMapping, PdoSlot,
    TransmissionType,
};
use crate::sync::SyncCobId;
use crate::time::TimeCobId;

/// The longest record: room for the communication group of 4 TPDOs and 4
/// RPDOs (403 bytes) and an application group of up to
/// `RECORD_CAPACITY - 12` bytes.
pub const RECORD_CAPACITY: usize = 512;

const MAGIC: [u8; 2] = *b"CO";
const FORMAT: u8 = 1;
/// Magic, version, group, layout, length.
const HEADER: usize = 10;
/// The CRC after the payload.
const TRAILER: usize = 2;

/// A group of parameters, stored as one record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ParameterGroup {
    /// 1010h/1011h sub 2: the communication parameters (1000h-1FFFh).
    Communication,
    /// 1010h/1011h sub 3: the application parameters (2000h-9FFFh).
    Application,
    /// The LSS slave's configuration (CiA 305 store configuration).
    Lss,
}

impl ParameterGroup {
    /// The group's number in the record (1, 2, 3).
    #[must_use]
    pub const fn raw(self) -> u8 {
        match self {
            ParameterGroup::Communication => 1,
            ParameterGroup::Application => 2,
            ParameterGroup::Lss => 3,
        }
    }
}

/// Why a [`ParameterStorage`] could not save, load or erase a record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum StorageError {
    /// The medium failed (write, read or erase error).
    #[error("the storage medium failed")]
    Medium,
    /// The record does not fit the medium (or the buffer).
    #[error("the record does not fit: {need} bytes, room for {room}")]
    NoRoom {
        /// The record's length.
        need: usize,
        /// The room there is.
        room: usize,
    },
}

/// Why a stored record was ignored (the power-on values stay).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum RecordError {
    /// Shorter than its header and trailer say.
    #[error("record truncated: {need} bytes needed, {got} stored")]
    Truncated {
        /// Bytes the header asks for.
        need: usize,
        /// Bytes stored.
        got: usize,
    },
    /// Not a record of this crate.
    #[error("no record magic")]
    Magic,
    /// Another format version.
    #[error("record format {0} unknown")]
    Format(u8),
    /// A record of another group.
    #[error("record of group {0}")]
    Group(u8),
    /// A record of another dictionary or PDO count.
    #[error("record layout {found:#x}, expected {expected:#x}")]
    Layout {
        /// This device's layout.
        expected: u32,
        /// The record's.
        found: u32,
    },
    /// The CRC does not match.
    #[error("record checksum wrong")]
    Checksum,
    /// A value the objects cannot hold (a reserved transmission type, an
    /// invalid mapping or COB-ID).
    #[error("record value invalid")]
    Value,
}

/// What the device did with its storage (a [`DeviceEvent::Storage`](super::DeviceEvent::Storage)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum StorageEvent {
    /// A group's record was stored (1010h, LSS store configuration).
    Stored(ParameterGroup),
    /// A group's record was erased (1011h): its defaults come back at the
    /// next reset that restores it.
    Erased(ParameterGroup),
    /// A group's stored values were loaded (boot, reset).
    Loaded(ParameterGroup),
    /// A group's record was ignored; the power-on values stay.
    Ignored {
        /// The group.
        group: ParameterGroup,
        /// Why.
        error: RecordError,
    },
    /// The storage failed (the SDO write was aborted with 06060000h, the
    /// LSS store answered with "storage media access error").
    Failed {
        /// The group.
        group: ParameterGroup,
        /// Why.
        error: StorageError,
    },
}

/// Where a device keeps its stored parameters: one record per
/// [`ParameterGroup`] (at most [`RECORD_CAPACITY`] bytes), kept until
/// saved again or erased. The application implements it over its flash,
/// EEPROM or file; [`RamStorage`] keeps the records in memory.
pub trait ParameterStorage {
    /// Replaces `group`'s record with `record`.
    ///
    /// # Errors
    /// The medium failed or has no room.
    fn save(&mut self, group: ParameterGroup, record: &[u8]) -> Result<(), StorageError>;

    /// Copies `group`'s record into `buf` and gives its length; 0 when
    /// there is none.
    ///
    /// # Errors
    /// The medium failed, or the record is longer than `buf`.
    fn load(&mut self, group: ParameterGroup, buf: &mut [u8]) -> Result<usize, StorageError>;

    /// Erases `group`'s record (nothing stored is not an error).
    ///
    /// # Errors
    /// The medium failed.
    fn erase(&mut self, group: ParameterGroup) -> Result<(), StorageError>;
}

/// A [`ParameterStorage`] in memory: `N` bytes per group (a test bench, or
/// a RAM that survives resets but not power).
///
/// ```
/// use canopen_codec::device::{ParameterGroup, ParameterStorage, RamStorage};
/// let mut ram = RamStorage::<16>::new();
/// ram.save(ParameterGroup::Lss, &[1, 2, 3]).unwrap();
/// let mut buf = [0; 16];
/// assert_eq!(ram.load(ParameterGroup::Lss, &mut buf), Ok(3));
/// ram.erase(ParameterGroup::Lss).unwrap();
/// assert_eq!(ram.load(ParameterGroup::Lss, &mut buf), Ok(0));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RamStorage<const N: usize = RECORD_CAPACITY> {
    records: [[u8; N]; 3],
    lens: [usize; 3],
}

impl<const N: usize> Default for RamStorage<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> RamStorage<N> {
    /// Nothing stored.
    #[must_use]
    pub const fn new() -> Self {
        RamStorage {
            records: [[0; N]; 3],
            lens: [0; 3],
        }
    }

    /// `group`'s record as stored (empty: none), e.g. to corrupt it in a
    /// test.
    pub fn record_mut(&mut self, group: ParameterGroup) -> &mut [u8] {
        let i = usize::from(group.raw() - 1);
        let len = self.lens.get(i).copied().unwrap_or(0);
        self.records
            .get_mut(i)
            .and_then(|r| r.get_mut(..len))
            .unwrap_or(&mut [])
    }
}

impl<const N: usize> ParameterStorage for RamStorage<N> {
    fn save(&mut self, group: ParameterGroup, record: &[u8]) -> Result<(), StorageError> {
        let i = usize::from(group.raw() - 1);
        let (Some(slot), Some(len)) = (self.records.get_mut(i), self.lens.get_mut(i)) else {
            return Err(StorageError::Medium);
        };
        let Some(dst) = slot.get_mut(..record.len()) else {
            return Err(StorageError::NoRoom {
                need: record.len(),
                room: N,
            });
        };
        dst.copy_from_slice(record);
        *len = record.len();
        Ok(())
    }

    fn load(&mut self, group: ParameterGroup, buf: &mut [u8]) -> Result<usize, StorageError> {
        let record = self.record_mut(group);
        let need = record.len();
        let Some(dst) = buf.get_mut(..need) else {
            return Err(StorageError::NoRoom {
                need,
                room: buf.len(),
            });
        };
        dst.copy_from_slice(record);
        Ok(need)
    }

    fn erase(&mut self, group: ParameterGroup) -> Result<(), StorageError> {
        if let Some(len) = self.lens.get_mut(usize::from(group.raw() - 1)) {
            *len = 0;
        }
        Ok(())
    }
}

// ----- the record ----------------------------------------------------------

/// Writes little-endian values into a buffer; past its end nothing is
/// written and [`finish`](Self::finish) fails.
struct Writer<'a> {
    buf: &'a mut [u8],
    len: usize,
    overflow: bool,
}

impl<'a> Writer<'a> {
    fn new(buf: &'a mut [u8]) -> Self {
        Writer {
            buf,
            len: 0,
            overflow: false,
        }
    }

    fn bytes(&mut self, bytes: &[u8]) {
        let end = self.len.saturating_add(bytes.len());
        match self.buf.get_mut(self.len..end) {
            Some(dst) => {
                dst.copy_from_slice(bytes);
                self.len = end;
            }
            None => self.overflow = true,
        }
    }

    fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }

    fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }

    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
}

/// Reads little-endian values off the front of a payload.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn u8(&mut self) -> Option<u8> {
        let [v, rest @ ..] = self.0 else { return None };
        self.0 = rest;
        Some(*v)
    }

    fn u16(&mut self) -> Option<u16> {
        let [a, b, rest @ ..] = self.0 else {
            return None;
        };
        self.0 = rest;
        Some(u16::from_le_bytes([*a, *b]))
    }

    fn u32(&mut self) -> Option<u32> {
        let [a, b, c, d, rest @ ..] = self.0 else {
            return None;
        };
        self.0 = rest;
        Some(u32::from_le_bytes([*a, *b, *c, *d]))
    }
}

/// Makes the record of `group` in `buf` around the payload `fill` writes;
/// gives its length.
fn encode(
    buf: &mut [u8],
    group: ParameterGroup,
    layout: u32,
    fill: impl FnOnce(&mut Writer<'_>),
) -> Result<usize, StorageError> {
    let mut w = Writer::new(buf);
    w.bytes(&MAGIC);
    w.u8(FORMAT);
    w.u8(group.raw());
    w.u32(layout);
    w.u16(0);
    fill(&mut w);
    let (len, overflow) = (w.len, w.overflow);
    let payload = len.saturating_sub(HEADER);
    let room = buf.len();
    let too_long = |need| StorageError::NoRoom { need, room };
    if overflow || payload > usize::from(u16::MAX) {
        return Err(too_long(len.max(room.saturating_add(1))));
    }
    if let Some(field) = buf.get_mut(8..HEADER) {
        field.copy_from_slice(&(payload as u16).to_le_bytes());
    }
    let crc = crate::sdo::crc16(buf.get(..len).unwrap_or(&[]));
    let end = len + TRAILER;
    let dst = buf.get_mut(len..end).ok_or(too_long(end))?;
    dst.copy_from_slice(&crc.to_le_bytes());
    Ok(end)
}

/// The payload of a record of `group` and `layout`, checked.
///
/// # Errors
/// What is wrong with the record.
pub fn decode_record(
    record: &[u8],
    group: ParameterGroup,
    layout: u32,
) -> Result<&[u8], RecordError> {
    let got = record.len();
    let [m0, m1, format, g, l0, l1, l2, l3, n0, n1, rest @ ..] = record else {
        return Err(RecordError::Truncated {
            need: HEADER + TRAILER,
            got,
        });
    };
    if [*m0, *m1] != MAGIC {
        return Err(RecordError::Magic);
    }
    if *format != FORMAT {
        return Err(RecordError::Format(*format));
    }
    let n = usize::from(u16::from_le_bytes([*n0, *n1]));
    let (Some(payload), Some([c0, c1])) = (rest.get(..n), rest.get(n..n + TRAILER)) else {
        return Err(RecordError::Truncated {
            need: HEADER + n + TRAILER,
            got,
        });
    };
    let covered = record.get(..HEADER + n).unwrap_or(&[]);
    if crate::sdo::crc16(covered) != u16::from_le_bytes([*c0, *c1]) {
        return Err(RecordError::Checksum);
    }
    if *g != group.raw() {
        return Err(RecordError::Group(*g));
    }
    let found = u32::from_le_bytes([*l0, *l1, *l2, *l3]);
    if found != layout {
        return Err(RecordError::Layout {
            expected: layout,
            found,
        });
    }
    Ok(payload)
}

/// The layout word of a communication record: the PDO counts.
const fn comm_layout(t: usize, r: usize) -> u32 {
    (t as u32) | (r as u32) << 8
}

/// The PDOs of a configuration in record order: RPDO 1..R, TPDO 1..T.
fn pdo_slots<const T: usize, const R: usize>() -> impl Iterator<Item = (PdoDirection, PdoNumber)> {
    let numbers = |dir, count: usize| {
        (0..count as u8).filter_map(move |n| PdoNumber::new(n).map(|n| (dir, n)))
    };
    numbers(PdoDirection::Receive, R).chain(numbers(PdoDirection::Transmit, T))
}

/// The communication record of `comm` and `pdos` in `buf`.
pub(super) fn encode_comm<const T: usize, const R: usize>(
    buf: &mut [u8],
    comm: &CommObjects,
    pdos: &PdoConfig<T, R>,
) -> Result<usize, StorageError> {
    encode(buf, ParameterGroup::Communication, comm_layout(T, R), |w| {
        w.u16(comm.heartbeat_ms);
        w.u16(comm.guard_time_ms);
        w.u8(comm.life_time_factor);
        w.u32(comm.sync_cob_id.raw());
        w.u32(comm.cycle_period_us);
        w.u32(comm.sync_window_us);
        w.u32(comm.time_cob_id.raw());
        w.u8(comm.sync_counter_overflow);
        #[cfg(feature = "heartbeat-consumer")]
        let consumers = comm.consumers();
        #[cfg(not(feature = "heartbeat-consumer"))]
        let consumers: &[crate::nmt::heartbeat::ConsumerEntry] = &[];
        w.u8(consumers.len() as u8);
        for i in 0..4 {
            w.u32(consumers.get(i).map_or(0, |e| e.to_u32()));
        }
        for (dir, n) in pdo_slots::<T, R>() {
            let slot = pdos.get(dir, n);
            w.u8(u8::from(slot.is_some()));
            let comm = slot.map_or(PdoCommParams::event_driven(PdoCobId::from_u32(0), 0), |s| {
                s.comm
            });
            w.u32(comm.cob_id.to_u32());
            w.u8(comm.transmission_type.to_u8());
            w.u16(comm.inhibit_time_100us);
            w.u8(comm.reserved);
            w.u16(comm.event_timer_ms);
            w.u8(slot.map_or(0, PdoSlot::count));
            for sub in 1..=8 {
                let entry = slot.and_then(|s| s.entry(sub));
                w.u32(entry.map_or(0, MappingEntry::to_u32));
            }
        }
    })
}

/// Puts a communication record's values into `comm` and `pdos`, all or
/// none.
pub(super) fn apply_comm<const T: usize, const R: usize>(
    record: &[u8],
    comm: &mut CommObjects,
    pdos: &mut PdoConfig<T, R>,
) -> Result<(), RecordError> {
    let payload = decode_record(record, ParameterGroup::Communication, comm_layout(T, R))?;
    let (mut new_comm, mut new_pdos) = (comm.clone(), *pdos);
    read_comm(&mut Reader(payload), &mut new_comm, &mut new_pdos).ok_or(RecordError::Value)?;
    (*comm, *pdos) = (new_comm, new_pdos);
    Ok(())
}

fn read_comm<const T: usize, const R: usize>(
    r: &mut Reader<'_>,
    comm: &mut CommObjects,
    pdos: &mut PdoConfig<T, R>,
) -> Option<()> {
    comm.heartbeat_ms = r.u16()?;
    comm.guard_time_ms = r.u16()?;
    comm.life_time_factor = r.u8()?;
    comm.sync_cob_id = SyncCobId::from_raw(r.u32()?);
    comm.sync_cob_id.id()?;
    comm.cycle_period_us = r.u32()?;
    comm.sync_window_us = r.u32()?;
    comm.time_cob_id = TimeCobId::from_raw(r.u32()?);
    comm.time_cob_id.id()?;
    comm.sync_counter_overflow = r.u8()?;
    if !crate::sync::valid_counter_overflow(comm.sync_counter_overflow) {
        return None;
    }
    let count = usize::from(r.u8()?);
    let mut consumers = [0u32; 4];
    for c in &mut consumers {
        *c = r.u32()?;
    }
    #[cfg(feature = "heartbeat-consumer")]
    {
        let entries = consumers.map(crate::nmt::heartbeat::ConsumerEntry::from_u32);
        comm.set_consumers(entries.get(..count)?);
    }
    #[cfg(not(feature = "heartbeat-consumer"))]
    let _ = (count, consumers);
    for (dir, n) in pdo_slots::<T, R>() {
        let present = r.u8()? == 1;
        let params = PdoCommParams {
            cob_id: PdoCobId::from_u32(r.u32()?),
            transmission_type: TransmissionType::from_u8(r.u8()?).ok()?,
            inhibit_time_100us: r.u16()?,
            reserved: r.u8()?,
            event_timer_ms: r.u16()?,
        };
        let count = usize::from(r.u8()?);
        let mut entries = [MappingEntry::default(); 8];
        for e in &mut entries {
            *e = MappingEntry::from_u32(r.u32()?);
        }
        if present {
            let mapping = PdoMapping::new(entries.get(..count)?).ok()?;
            pdos.insert(dir, n, PdoSlot::new(params, &mapping));
        }
    }
    r.0.is_empty().then_some(())
}

/// The application record of the parameter bytes `parameters`.
pub(super) fn encode_app(
    buf: &mut [u8],
    layout: u32,
    parameters: &[u8],
) -> Result<usize, StorageError> {
    encode(buf, ParameterGroup::Application, layout, |w| {
        w.bytes(parameters);
    })
}

/// Copies an application record's parameter bytes into `parameters` (the
/// same length).
pub(super) fn apply_app(
    record: &[u8],
    layout: u32,
    parameters: &mut [u8],
) -> Result<(), RecordError> {
    let payload = decode_record(record, ParameterGroup::Application, layout)?;
    if payload.len() != parameters.len() {
        return Err(RecordError::Value);
    }
    parameters.copy_from_slice(payload);
    Ok(())
}

/// The LSS record: the pending node-ID and bit timing.
#[cfg(feature = "lss")]
pub(super) fn encode_lss(
    buf: &mut [u8],
    node: Option<NodeId>,
    bit_timing: Option<(u8, u8)>,
) -> Result<usize, StorageError> {
    encode(buf, ParameterGroup::Lss, 0, |w| {
        w.u8(node.map_or(0xFF, NodeId::raw));
        let (table, index) = bit_timing.unwrap_or((0, 0));
        w.bytes(&[u8::from(bit_timing.is_some()), table, index]);
    })
}

/// The node-ID and bit timing of an LSS record.
#[cfg(feature = "lss")]
pub(super) fn decode_lss(record: &[u8]) -> Result<LssStored, RecordError> {
    let payload = decode_record(record, ParameterGroup::Lss, 0)?;
    let [node, timed, table, index] = payload else {
        return Err(RecordError::Value);
    };
    let node = match (*node, NodeId::new(*node)) {
        (0xFF, _) => None,
        (_, Some(id)) => Some(id),
        _ => return Err(RecordError::Value),
    };
    Ok((node, (*timed == 1).then_some((*table, *index))))
}

/// What an LSS record holds: node-ID, bit timing (table, index).
#[cfg(feature = "lss")]
pub(super) type LssStored = (Option<NodeId>, Option<(u8, u8)>);

#[cfg(test)]
#[path = "store_tests.rs"]
mod tests;
