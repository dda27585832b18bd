//! The reader: the file's data groups opened (their channel groups'
//! layouts read once), each read as a stream of records, the bus-logging
//! records decoded and merged by time across the data groups.

use alloc::collections::BTreeSet;
use alloc::vec::Vec;

use super::blocks::{block, head, id, Source, HEADER};
use super::data::Stream;
use super::layout::{layout, Event, Field, Layout};
use super::{Mf4Error, Mf4Event, Mf4Frame, Mf4Header, FILE_MAGIC};
use crate::clock::Timestamp;
use crate::frame::{CanFrame, CanId, MAX_STANDARD_ID};
use crate::trace::inflate::Inflate;
use crate::trace::{RxTx, Unsupported};

/// The largest record read (data and invalidation bytes).
const MAX_RECORD: u64 = 1 << 20;
/// The most data groups with bus logging read at once.
const MAX_DATA_GROUPS: usize = 4096;
/// The most bytes the data groups' streams hold at once (each holds one
/// data block: many groups of large compressed blocks would hold more).
pub const MAX_HELD: usize = 256 << 20;

/// What a channel group's records are.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Records {
    /// CAN bus logging.
    Bus(Layout),
    /// Fixed-size records of another kind, skipped.
    Other,
    /// Variable-length signal data (u32 length, bytes), skipped.
    Variable,
}

/// The most bytes of one variable-length value kept (a CAN FD frame's).
const MAX_VALUE: usize = 64;

/// A variable-length value: its offset in its signal data, its first
/// bytes.
#[derive(Debug, Clone, Copy)]
struct Value {
    offset: u64,
    len: usize,
    bytes: [u8; MAX_VALUE],
}

impl Value {
    fn bytes(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or(&self.bytes)
    }
}

/// Where a bus group's variable-length `DataBytes` are.
#[derive(Debug)]
enum Signal {
    /// Fixed `DataBytes` (or none).
    None,
    /// A variable-length channel group of the same data group (MDF 4.2).
    Group { record_id: u64 },
    /// A `##SD` chain, read forward: the offset read up to.
    Data { stream: Stream, pos: u64 },
}

/// A channel group of a data group.
#[derive(Debug)]
struct Group {
    record_id: u64,
    /// Data and invalidation bytes of one record.
    size: usize,
    records: Records,
    /// Records of it read.
    index: u64,
    /// A variable-length group: the offset of its next value.
    pos: u64,
    signal: Signal,
}

/// One data group being read.
#[derive(Debug)]
struct Cursor {
    stream: Stream,
    record_id_size: u8,
    groups: Vec<Group>,
    /// The last value of a variable-length group: its record id and value.
    last: Option<(u64, Value)>,
    /// Whether a group reads `##SD` signal data (a stream of its own).
    signals: bool,
    /// The next event, read ahead for the merge by time.
    head: Option<Mf4Event>,
    done: bool,
}

/// Reads the CAN frames of an MF4 file through its [`Source`] (`&[u8]`
/// for a file in memory, [`SeekSource`](super::SeekSource) for one read
/// in place). See the [module docs](super).
///
/// Call [`next`](Self::next) until it returns `None`; an error that is
/// not [fatal](Mf4Error::is_fatal) skipped one record, and reading goes
/// on.
#[derive(Debug)]
pub struct Mf4Reader<S> {
    src: S,
    header: Mf4Header,
    start_ns: u64,
    cursors: Vec<Cursor>,
    failed: Option<Mf4Error>,
    /// [`MAX_HELD`] (smaller in tests).
    pub(super) held_limit: usize,
}

impl Mf4Reader<&'static [u8]> {
    /// True when `bytes` (the start of a file) begin with `MDF     `.
    #[must_use]
    pub fn detect(bytes: &[u8]) -> bool {
        bytes.starts_with(&FILE_MAGIC)
    }
}

impl<S: Source> Mf4Reader<S> {
    /// Opens the MF4 file `src`: reads its `##ID` and `##HD` blocks and
    /// the channels of every data group (no data yet).
    pub fn new(mut src: S) -> Result<Self, Mf4Error> {
        let file_size = src.size();
        let mut id_block = [0u8; 64];
        let magic = id_block.get_mut(..FILE_MAGIC.len()).unwrap_or(&mut []);
        if src.read_at(0, magic).is_err() || !Mf4Reader::detect(magic) {
            return Err(Mf4Error::NotMf4);
        }
        if src.read_at(0, &mut id_block).is_err() {
            return Err(Mf4Error::PastEnd { at: 0 });
        }
        let version = u16::from_le_bytes([
            id_block.get(28).copied().unwrap_or(0),
            id_block.get(29).copied().unwrap_or(0),
        ]);
        if version < 400 {
            return Err(Mf4Error::Version { version });
        }
        let mut program = [0u8; 8];
        if let Some(p) = id_block.get(16..24) {
            program.copy_from_slice(p);
        }
        let file: &mut dyn Source = &mut src;
        let hd = block(file, 64, &[id::HD])?;
        let start_ns = hd.u64(0);
        let header = Mf4Header {
            version,
            program,
            start: (start_ns != 0)
                .then(|| Timestamp::from_micros(start_ns.saturating_add(500) / 1000)),
        };
        let mut hops = file_size / HEADER + 1;
        // Data and channel groups met: one met again is a loop.
        let mut met = BTreeSet::new();
        let mut cursors = Vec::new();
        let mut dg_at = hd.link(0);
        while dg_at != 0 {
            if !met.insert(dg_at) {
                return Err(Mf4Error::LinkCycle { what: "data group" });
            }
            let dg = block(file, dg_at, &[id::DG])?;
            let record_id_size = dg.u8(0);
            if !matches!(record_id_size, 0 | 1 | 2 | 4 | 8) {
                return Err(Mf4Error::RecordIdSize {
                    at: dg_at,
                    size: record_id_size,
                });
            }
            let mut groups = Vec::new();
            let mut cg_at = dg.link(1);
            while cg_at != 0 {
                if !met.insert(cg_at) {
                    return Err(Mf4Error::LinkCycle {
                        what: "channel group",
                    });
                }
                let cg = block(file, cg_at, &[id::CG])?;
                let flags = cg.u16(16);
                let size = u64::from(cg.u32(24)) + u64::from(cg.u32(28));
                let records = if flags & 1 != 0 {
                    Records::Variable
                } else {
                    match layout(file, &cg, &mut hops)? {
                        Some(l) => Records::Bus(l),
                        None => Records::Other,
                    }
                };
                if size > MAX_RECORD {
                    return Err(Mf4Error::RecordTooLarge { size });
                }
                let signal = match records {
                    Records::Bus(Layout {
                        vlsd: Some((_, data)),
                        ..
                    }) if data != 0 => {
                        let h = head(file, data, &[id::CG, id::SD, id::DZ, id::DL, id::HL])?;
                        if h.id == id::CG {
                            Signal::Group {
                                record_id: block(file, data, &[id::CG])?.u64(0),
                            }
                        } else {
                            Signal::Data {
                                stream: Stream::signal(file_size, data),
                                pos: 0,
                            }
                        }
                    }
                    _ => Signal::None,
                };
                groups.push(Group {
                    record_id: cg.u64(0),
                    size: size as usize,
                    records,
                    index: 0,
                    pos: 0,
                    signal,
                });
                cg_at = cg.link(0);
            }
            if record_id_size == 0 && groups.len() > 1 {
                return Err(Mf4Error::SortedGroups { at: dg_at });
            }
            if groups.iter().any(|g| matches!(g.records, Records::Bus(_))) {
                if cursors.len() >= MAX_DATA_GROUPS {
                    return Err(Mf4Error::LinkCycle { what: "data group" });
                }
                cursors.push(Cursor {
                    stream: Stream::new(file_size, dg.link(2)),
                    record_id_size,
                    signals: groups
                        .iter()
                        .any(|g| matches!(g.signal, Signal::Data { .. })),
                    groups,
                    last: None,
                    head: None,
                    done: false,
                });
            }
            dg_at = dg.link(0);
        }
        Ok(Mf4Reader {
            src,
            header,
            start_ns,
            cursors,
            failed: None,
            held_limit: MAX_HELD,
        })
    }

    /// What the file's identification and header say.
    #[must_use]
    pub const fn header(&self) -> Mf4Header {
        self.header
    }

    /// The next frame or event in time order (ties in data group order),
    /// `##DZ` blocks inflated by `zlib`; `None` at the end.
    pub fn next(&mut self, zlib: &mut dyn Inflate) -> Result<Option<Mf4Event>, Mf4Error> {
        if let Some(e) = self.failed {
            return Err(e);
        }
        let start_ns = self.start_ns;
        // Only a cursor whose head was taken reads; the bytes held are
        // summed again when one of them holds more.
        let mut grew = false;
        for c in &mut self.cursors {
            if c.head.is_none() && !c.done {
                let before = c.held();
                match c.next(start_ns, &mut self.src, zlib) {
                    Ok(Some(e)) => c.head = Some(e),
                    Ok(None) => c.done = true,
                    Err(e) => {
                        if e.is_fatal() {
                            self.failed = Some(e);
                        }
                        return Err(e);
                    }
                }
                grew |= c.held() > before;
            }
        }
        if grew {
            let held = self
                .cursors
                .iter()
                .map(Cursor::held)
                .fold(0usize, usize::saturating_add);
            if held > self.held_limit {
                let e = Mf4Error::TooMuchHeld { held: held as u64 };
                self.failed = Some(e);
                return Err(e);
            }
        }
        // The earliest head, the first of equal ones.
        let mut first: Option<(u64, &mut Option<Mf4Event>)> = None;
        for c in &mut self.cursors {
            let Some(e) = &c.head else { continue };
            let key = time_of(e).map_or(0, Timestamp::as_micros);
            if first.as_ref().is_none_or(|(k, _)| key < *k) {
                first = Some((key, &mut c.head));
            }
        }
        Ok(first.and_then(|(_, head)| head.take()))
    }
}

/// An event's time.
fn time_of(e: &Mf4Event) -> Option<Timestamp> {
    match e {
        Mf4Event::Frame(f) => f.timestamp,
        Mf4Event::Unsupported { timestamp, .. } => *timestamp,
    }
}

impl Cursor {
    /// The bytes its streams hold.
    fn held(&self) -> usize {
        if !self.signals {
            return self.stream.held();
        }
        self.groups
            .iter()
            .map(|g| match &g.signal {
                Signal::Data { stream, .. } => stream.held(),
                _ => 0,
            })
            .fold(self.stream.held(), usize::saturating_add)
    }

    /// The next bus-logging event of this data group.
    fn next(
        &mut self,
        start_ns: u64,
        src: &mut dyn Source,
        zlib: &mut dyn Inflate,
    ) -> Result<Option<Mf4Event>, Mf4Error> {
        if self.record_id_size == 0 && self.groups.first().is_none_or(|g| g.size == 0) {
            // A sorted group of 0-byte records holds no frames (and
            // reading them would take no bytes).
            return Ok(None);
        }
        loop {
            let record_id = match self.record_id_size {
                0 => self.groups.first().map_or(0, |g| g.record_id),
                n => match self.stream.take(usize::from(n), src, zlib)? {
                    Some(bytes) => bytes.iter().rev().fold(0u64, |v, &b| v << 8 | u64::from(b)),
                    None => return Ok(None),
                },
            };
            let Some(group) = self
                .groups
                .iter_mut()
                .find(|g| self.record_id_size == 0 || g.record_id == record_id)
            else {
                return Err(Mf4Error::UnknownRecordId { record_id });
            };
            let index = group.index;
            group.index = index.saturating_add(1);
            match &group.records {
                Records::Variable => {
                    let offset = group.pos;
                    let value = read_value(&mut self.stream, offset, src, zlib)?
                        .ok_or(Mf4Error::RecordPastEnd { need: 4, left: 0 })?;
                    group.pos = offset.saturating_add(4).saturating_add(value.1);
                    self.last = Some((group.record_id, value.0));
                }
                Records::Other => {
                    let size = group.size;
                    if self.stream.take(size, src, zlib)?.is_none() && self.record_id_size == 0 {
                        return Ok(None);
                    }
                }
                Records::Bus(l) => {
                    let size = group.size;
                    let Some(record) = self.stream.take(size, src, zlib)? else {
                        if self.record_id_size == 0 {
                            return Ok(None);
                        }
                        return Err(Mf4Error::RecordPastEnd {
                            need: size,
                            left: 0,
                        });
                    };
                    let value = match (&mut group.signal, l.vlsd) {
                        (Signal::None, _) | (_, None) => None,
                        (signal, Some((field, _))) => Some(
                            field
                                .uint(record)
                                .ok_or(Mf4Error::MissingField { field: "DataBytes" })
                                .and_then(|offset| value_at(signal, self.last, offset, src, zlib)),
                        ),
                    };
                    let value = match value {
                        Some(Ok(v)) => Some(v),
                        Some(Err(e)) => return Err(e),
                        None => None,
                    };
                    let data = value.as_ref().map(Value::bytes);
                    return decode(l, record, data, index, start_ns).map(Some);
                }
            }
        }
    }
}

/// Reads one variable-length value (u32 length, bytes) at `offset` of
/// `stream`: the value (its first [`MAX_VALUE`] bytes) and its length;
/// `None` at the end of the data.
fn read_value(
    stream: &mut Stream,
    offset: u64,
    src: &mut dyn Source,
    zlib: &mut dyn Inflate,
) -> Result<Option<(Value, u64)>, Mf4Error> {
    let Some(len) = stream.take(4, src, zlib)? else {
        return Ok(None);
    };
    let len = len.iter().rev().fold(0u64, |v, &b| v << 8 | u64::from(b));
    let keep = usize::try_from(len).unwrap_or(MAX_VALUE).min(MAX_VALUE);
    let mut value = Value {
        offset,
        len: keep,
        bytes: [0; MAX_VALUE],
    };
    let Some(bytes) = stream.take(keep, src, zlib)? else {
        return Err(Mf4Error::RecordPastEnd {
            need: keep,
            left: 0,
        });
    };
    if let Some(to) = value.bytes.get_mut(..bytes.len()) {
        to.copy_from_slice(bytes);
    }
    stream.skip(len.saturating_sub(keep as u64), src, zlib)?;
    Ok(Some((value, len)))
}

/// The variable-length value at `offset` of a bus group's signal data:
/// the last value of its variable-length group, or read forward in its
/// `##SD` chain (an offset behind the one read, or past the end, names no
/// value).
fn value_at(
    signal: &mut Signal,
    last: Option<(u64, Value)>,
    offset: u64,
    src: &mut dyn Source,
    zlib: &mut dyn Inflate,
) -> Result<Value, Mf4Error> {
    let none = Mf4Error::SignalOffset { offset };
    match signal {
        Signal::None => Err(none),
        Signal::Group { record_id } => match last {
            Some((id, v)) if id == *record_id && v.offset == offset => Ok(v),
            _ => Err(none),
        },
        Signal::Data { stream, pos } => {
            let ahead = offset.checked_sub(*pos).ok_or(none)?;
            let read = stream
                .skip(ahead, src, zlib)
                .and_then(|()| read_value(stream, offset, src, zlib));
            let (value, len) = match read {
                Ok(Some(v)) => v,
                Ok(None) | Err(Mf4Error::RecordPastEnd { .. }) => {
                    // Past the end: nothing further can be read.
                    *pos = u64::MAX;
                    return Err(none);
                }
                Err(e) => return Err(e),
            };
            *pos = offset.saturating_add(4).saturating_add(len);
            Ok(value)
        }
    }
}

/// The record's time: the start plus its seconds, to the nearest
/// microsecond.
fn timestamp(l: &Layout, record: &[u8], index: u64, start_ns: u64) -> Option<Timestamp> {
    let s = l.time.seconds(record, index)?;
    let ns = s * 1e9;
    // Round half away from zero (`as` saturates, never panics).
    let ns = if ns >= 0.0 { ns + 0.5 } else { ns - 0.5 };
    // Within 285 years of the start (any real log) in 64 bits, which
    // costs less than 128 per record.
    let total = if ns.abs() < 9e18 {
        i128::from(start_ns).checked_add(i128::from(ns as i64))?
    } else {
        i128::from(start_ns).checked_add(ns as i128)?
    };
    // Negative (before 1970) below a half microsecond: no time.
    let half_up = u128::try_from(total.checked_add(500)?).ok()?;
    let us = match u64::try_from(half_up) {
        Ok(v) => v / 1000,
        Err(_) => u64::try_from(half_up / 1000).ok()?,
    };
    Some(Timestamp::from_micros(us))
}

/// A field's value, or the error naming it.
fn need(field: Option<Field>, record: &[u8], name: &'static str) -> Result<u64, Mf4Error> {
    field
        .and_then(|f| f.uint(record))
        .ok_or(Mf4Error::MissingField { field: name })
}

/// One bus-logging record as an event.
fn decode(
    l: &Layout,
    record: &[u8],
    value: Option<&[u8]>,
    index: u64,
    start_ns: u64,
) -> Result<Mf4Event, Mf4Error> {
    let timestamp = timestamp(l, record, index, start_ns);
    let unsupported = |what| Ok(Mf4Event::Unsupported { what, timestamp });
    match l.event {
        Event::Error => return unsupported(Unsupported::ErrorFrame),
        Event::Other => return unsupported(Unsupported::Event),
        Event::Data | Event::Remote => {}
    }
    let flag = |f: Option<Field>| f.and_then(|f| f.uint(record)).is_some_and(|v| v != 0);
    if flag(l.edl) {
        return unsupported(Unsupported::CanFd);
    }
    let raw = need(l.id, record, "ID")?;
    let extended = flag(l.ide) || raw & 0x8000_0000 != 0;
    let raw = (raw & 0x1FFF_FFFF) as u32;
    let id = if extended {
        CanId::extended(raw)
    } else if raw <= u32::from(MAX_STANDARD_ID) {
        CanId::standard(raw as u16)
    } else {
        None
    }
    .ok_or(Mf4Error::BadId { raw })?;
    let frame = if l.event == Event::Remote {
        let dlc = need(l.dlc.or(l.data_length), record, "DLC")?;
        if dlc > 8 {
            return Err(Mf4Error::BadDlc { dlc });
        }
        CanFrame::remote(id, dlc as u8).map_err(|_| Mf4Error::BadDlc { dlc })?
    } else {
        let bytes = value
            .or_else(|| l.data_bytes.and_then(|f| f.bytes(record)))
            .ok_or(Mf4Error::MissingField { field: "DataBytes" })?;
        let length = match (l.data_length.or(l.dlc), value) {
            (None, Some(v)) => v.len() as u64,
            (field, _) => need(field, record, "DataLength")?,
        };
        if length > 8 {
            return unsupported(Unsupported::CanFd);
        }
        let data = bytes
            .get(..length as usize)
            .ok_or(Mf4Error::DataPastField { length })?;
        CanFrame::new(id, data).map_err(|_| Mf4Error::DataPastField { length })?
    };
    Ok(Mf4Event::Frame(Mf4Frame {
        timestamp,
        channel: l.bus_channel.and_then(|f| f.uint(record)),
        direction: l.dir.and_then(|f| direction(f, record)),
        frame,
    }))
}

/// `Dir`: 0 Rx, 1 Tx, or the text `Rx` / `Tx`.
fn direction(f: Field, record: &[u8]) -> Option<RxTx> {
    if f.text {
        return match f.bytes(record)? {
            [b'T', b'x', ..] => Some(RxTx::Tx),
            [b'R', b'x', ..] => Some(RxTx::Rx),
            _ => None,
        };
    }
    match f.uint(record)? {
        0 => Some(RxTx::Rx),
        1 => Some(RxTx::Tx),
        _ => None,
    }
}
