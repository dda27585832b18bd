//! The pcap / pcapng reader's state machine: bytes collected into one
//! fixed buffer, then acted on by what they are (file header, record
//! header, block header, fields, options, packet data); a whole packet
//! at hand in the caller's chunk is read where it lies (the usual case).

use super::socketcan::{self, Packet};
use super::{
    Flavor, PcapError, PcapEvent, BYTE_ORDER_MAGIC, EPB, IDB, MAX_BLOCK, MAX_INTERFACES,
    MAX_RECORD, PB, SHB, SPB,
};
use crate::clock::Timestamp;
use crate::trace::fields::field;

/// What is kept of a packet: a CAN FD frame (16-byte header, 64 bytes).
const BUF: usize = 96;

/// A byte order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Order {
    Little,
    Big,
}

/// The field readers of [`Order`], one per width: the field's bytes at
/// `at` (zeros past the end of `b`) as a number in this byte order.
macro_rules! order_fields {
    ($($ty:ident),+) => {
        impl Order {
            $(
                fn $ty(self, b: &[u8], at: usize) -> $ty {
                    let a = field(b, at);
                    match self {
                        Order::Little => $ty::from_le_bytes(a),
                        Order::Big => $ty::from_be_bytes(a),
                    }
                }
            )+
        }
    };
}

order_fields!(u16, u32, u64);

/// An interface of a pcapng section (or the link of a pcap file).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Interface {
    pub(super) link_type: u16,
    pub(super) snap_len: u32,
    /// `if_tsresol` (6: microseconds).
    pub(super) resolution: u8,
    /// `if_tsoffset`, seconds.
    pub(super) offset: i64,
}

pub(super) const NO_INTERFACE: Interface = Interface {
    link_type: 0,
    snap_len: 0,
    resolution: 6,
    offset: 0,
};

/// What the collected bytes are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    /// The first four bytes.
    Magic,
    /// The rest of a pcap file header (20 bytes).
    PcapHeader,
    /// A pcap record header (16 bytes).
    Record,
    /// A packet's data (pcap or pcapng).
    Data(Packet),
    /// A block's type and length (8 bytes).
    BlockHead,
    /// A Section Header Block's byte-order magic (4 bytes).
    ShbMagic,
    /// A Section Header Block's versions and section length (12 bytes).
    ShbRest,
    /// An Interface Description Block's link type, reserved field and
    /// snap length (8 bytes).
    Idb,
    /// An option's code and length (4 bytes) of interface `n`.
    Option(usize),
    /// An option's value (`if_tsresol` or `if_tsoffset`) of interface `n`.
    Value(usize, u16),
    /// An Enhanced Packet Block's or a Packet Block's fixed fields (20
    /// bytes).
    PacketHead(u32),
    /// A Simple Packet Block's original length (4 bytes).
    SpbHead,
    /// A block's trailing length (4 bytes, after the rest is skipped).
    Tail,
}

/// A pcap or pcapng reader: feed it the file's bytes in chunks of any
/// size ([`PcapReader::read`]), then call [`PcapReader::finish`].
#[derive(Debug, Clone)]
pub struct PcapReader {
    state: State,
    flavor: Option<Flavor>,
    order: Order,
    buf: [u8; BUF],
    /// Bytes in `buf`.
    have: usize,
    /// Bytes to collect before the state acts.
    want: usize,
    /// Bytes to discard before collecting.
    skip: u64,
    /// Bytes of the current block or record not yet consumed.
    left: u64,
    /// Bytes consumed from the file.
    offset: u64,
    /// The current block's type, length and start.
    block: (u32, u32, u64),
    /// The interfaces of the section (pcap: one, the file's link).
    interfaces: [Interface; MAX_INTERFACES],
    /// Interfaces described in the section (also past those kept).
    described: usize,
    failed: Option<PcapError>,
}

impl Default for PcapReader {
    fn default() -> Self {
        Self::new()
    }
}

impl PcapReader {
    /// A reader at the start of a file.
    #[must_use]
    pub const fn new() -> Self {
        PcapReader {
            state: State::Magic,
            flavor: None,
            order: Order::Little,
            buf: [0; BUF],
            have: 0,
            want: 4,
            skip: 0,
            left: 0,
            offset: 0,
            block: (0, 0, 0),
            interfaces: [NO_INTERFACE; MAX_INTERFACES],
            described: 0,
            failed: None,
        }
    }

    /// The format, once its magic number has been read.
    #[must_use]
    pub const fn flavor(&self) -> Option<Flavor> {
        self.flavor
    }

    /// The next packet from the file's bytes `input` (advanced past what
    /// is read); `None` when `input` is used up. A fatal error comes back
    /// from every later call.
    pub fn read(&mut self, input: &mut &[u8]) -> Result<Option<PcapEvent>, PcapError> {
        if let Some(e) = self.failed {
            return Err(e);
        }
        loop {
            let r = match self.whole_packet(input) {
                Some(r) => r.map(Some),
                None => {
                    if !self.fill(input) {
                        return Ok(None);
                    }
                    let have = core::mem::take(&mut self.have);
                    self.step(have)
                }
            };
            match r {
                Ok(None) => {}
                Ok(Some(event)) => return Ok(Some(event)),
                Err(e) => {
                    if e.is_fatal() {
                        self.failed = Some(e);
                    }
                    return Err(e);
                }
            }
        }
    }

    /// At the end of the file: an error when it ends inside its header, a
    /// block or a record (or is empty).
    pub fn finish(&mut self) -> Result<(), PcapError> {
        if let Some(e) = self.failed {
            return Err(e);
        }
        let between = self.have == 0 && self.skip == 0;
        match self.state {
            State::Magic if self.have == 0 => Err(PcapError::NotPcap),
            State::Magic | State::PcapHeader => Err(PcapError::Truncated("the file header")),
            State::Record if between => Ok(()),
            State::BlockHead if between => Ok(()),
            State::Record | State::Data(_) if self.flavor != Some(Flavor::PcapNg) => {
                Err(PcapError::Truncated("a packet record"))
            }
            _ => Err(PcapError::Truncated("a block")),
        }
    }

    /// The usual case, a whole packet at hand where the next begins (a
    /// pcap record, or an Enhanced Packet Block up to its trailing
    /// length): read where it lies, with no copy, and the reader left as
    /// the byte-by-byte reading leaves it after the packet. `None`, with
    /// nothing read, for anything else (another block, a packet cut by
    /// the chunk's end, any error of the file's structure), which the
    /// byte-by-byte reading reads.
    fn whole_packet(&mut self, input: &mut &[u8]) -> Option<Result<PcapEvent, PcapError>> {
        if self.have != 0 || self.skip != 0 {
            return None;
        }
        let o = self.order;
        let (packet, at, size) = match self.state {
            State::Record => {
                let packet = self.record(input.get(..16)?).ok()?;
                (packet, 16, 16 + usize::try_from(packet.captured).ok()?)
            }
            State::BlockHead if o.u32(input, 0) == EPB => {
                let length = o.u32(input, 4);
                let block = input.get(..usize::try_from(length).ok()?)?;
                let fields = block.get(8..28)?;
                let (interface, units, captured) = packet_fields(o, EPB, fields);
                let tail = block.len().checked_sub(4)?;
                if !block_length_ok(length)
                    || o.u32(block, tail) != length
                    || u64::from(captured) > u64::from(length).checked_sub(32)?
                {
                    return None;
                }
                let i = self.described(interface).ok()?;
                self.block = (EPB, length, self.offset);
                let packet = Packet {
                    interface,
                    link_type: i.link_type,
                    captured,
                    timestamp: block_time(units, i),
                };
                (packet, 28, block.len())
            }
            _ => return None,
        };
        let kept = usize::try_from(packet.captured).unwrap_or(BUF).min(BUF);
        let data = input.get(at..)?.get(..kept)?;
        let rest = input.get(size..)?;
        let event = socketcan::event(packet, data);
        *input = rest;
        self.offset = self.offset.saturating_add(size as u64);
        self.left = 0;
        Some(event)
    }

    /// Skips what is to be skipped, then collects up to `want` bytes:
    /// true once they are all in `buf`.
    fn fill(&mut self, input: &mut &[u8]) -> bool {
        if self.skip > 0 {
            let n = usize::try_from(self.skip)
                .unwrap_or(usize::MAX)
                .min(input.len());
            *input = input.get(n..).unwrap_or(&[]);
            self.consumed(n);
            self.skip -= n as u64;
            if self.skip > 0 {
                return false;
            }
        }
        let want = self.want.min(BUF);
        let n = want.saturating_sub(self.have).min(input.len());
        if let (Some(to), Some(from)) = (self.buf.get_mut(self.have..self.have + n), input.get(..n))
        {
            to.copy_from_slice(from);
        }
        *input = input.get(n..).unwrap_or(&[]);
        self.have += n;
        self.consumed(n);
        self.have >= want
    }

    fn consumed(&mut self, n: usize) {
        self.offset = self.offset.saturating_add(n as u64);
        self.left = self.left.saturating_sub(n as u64);
    }

    /// Collect `n` bytes next, in state `state`.
    fn next(&mut self, state: State, n: usize) {
        self.state = state;
        self.want = n;
    }

    /// The bytes of the block left before its trailing length.
    const fn room(&self) -> u64 {
        self.left.saturating_sub(4)
    }

    /// Collect `n` bytes of the block's body next, in state `state`, or
    /// (when the block has no room for them) the block is too short.
    fn field(&mut self, state: State, n: usize) -> Result<(), PcapError> {
        if (n as u64) > self.room() {
            return Err(self.too_short());
        }
        self.next(state, n);
        Ok(())
    }

    const fn too_short(&self) -> PcapError {
        PcapError::BlockTooShort {
            block_type: self.block.0,
            offset: self.block.2,
        }
    }

    /// Skip to the block's trailing length.
    fn skip_to_tail(&mut self) {
        self.skip = self.room();
        self.next(State::Tail, 4);
    }

    /// Acts on the `want` bytes collected.
    fn step(&mut self, have: usize) -> Result<Option<PcapEvent>, PcapError> {
        let buf = self.buf;
        let b = buf.get(..have).unwrap_or(&[]);
        let o = self.order;
        match self.state {
            State::Magic => self.magic(b),
            State::PcapHeader => {
                let (major, minor) = (o.u16(b, 0), o.u16(b, 2));
                if major != 2 {
                    return Err(PcapError::Version { major, minor });
                }
                let nanos = self.flavor == Some(Flavor::Pcap { nanos: true });
                if let Some(i) = self.interfaces.first_mut() {
                    *i = Interface {
                        link_type: (o.u32(b, 16) & 0xFFFF) as u16,
                        snap_len: o.u32(b, 12),
                        resolution: if nanos { 9 } else { 6 },
                        offset: 0,
                    };
                }
                self.described = 1;
                self.next(State::Record, 16);
                Ok(None)
            }
            State::Record => {
                let packet = self.record(b)?;
                self.left = u64::from(packet.captured);
                self.data(packet)
            }
            State::Data(packet) => {
                let event = socketcan::event(packet, b);
                if self.flavor == Some(Flavor::PcapNg) {
                    self.skip_to_tail();
                } else {
                    self.skip = self.left;
                    self.next(State::Record, 16);
                }
                event.map(Some)
            }
            State::BlockHead => self.block_head(b),
            State::ShbMagic => {
                self.order = match o.u32(b, 8) {
                    BYTE_ORDER_MAGIC => o,
                    m if m.swap_bytes() == BYTE_ORDER_MAGIC => match o {
                        Order::Little => Order::Big,
                        Order::Big => Order::Little,
                    },
                    _ => {
                        return Err(PcapError::ByteOrder {
                            offset: self.block.2,
                        })
                    }
                };
                let length = self.order.u32(b, 4);
                self.start_block(SHB, length, self.offset.saturating_sub(12))?;
                // 12 bytes of the block were read: type, length, magic.
                self.left = u64::from(length).saturating_sub(12);
                self.field(State::ShbRest, 12)?;
                Ok(None)
            }
            State::ShbRest => {
                let (major, minor) = (o.u16(b, 0), o.u16(b, 2));
                if major != 1 {
                    return Err(PcapError::Version { major, minor });
                }
                self.described = 0;
                self.skip_to_tail();
                Ok(None)
            }
            State::Idb => {
                let n = self.described;
                self.described = n.saturating_add(1);
                if let Some(i) = self.interfaces.get_mut(n) {
                    *i = Interface {
                        link_type: o.u16(b, 0),
                        snap_len: o.u32(b, 4),
                        ..NO_INTERFACE
                    };
                }
                self.option(n)
            }
            State::Option(n) => {
                let (code, length) = (o.u16(b, 0), o.u16(b, 2));
                let padded = (u64::from(length) + 3) & !3;
                if code == 0 {
                    self.skip_to_tail();
                } else if padded > self.room() {
                    return Err(self.too_short());
                } else if matches!((code, length), (9, 1) | (14, 8)) {
                    self.skip = 0;
                    self.next(State::Value(n, code), usize::from(length));
                } else {
                    self.skip = padded;
                    return self.option(n);
                }
                Ok(None)
            }
            State::Value(n, code) => {
                if let Some(i) = self.interfaces.get_mut(n) {
                    if code == 9 {
                        i.resolution = b.first().copied().unwrap_or(6);
                    } else {
                        i.offset = o.u64(b, 0) as i64;
                    }
                }
                // The value's padding.
                self.skip = (4 - (self.want as u64 % 4)) % 4;
                self.option(n)
            }
            State::PacketHead(block_type) => {
                let (interface, ts, captured) = packet_fields(o, block_type, b);
                let i = self.interface(interface)?;
                if u64::from(captured) > self.room() {
                    self.skip_to_tail();
                    return Err(PcapError::CapturedPastBlock { captured });
                }
                self.data(Packet {
                    interface,
                    link_type: i.link_type,
                    captured,
                    timestamp: block_time(ts, i),
                })
            }
            State::SpbHead => {
                let i = self.interface(0)?;
                let mut captured = u64::from(o.u32(b, 0)).min(self.room());
                if i.snap_len != 0 {
                    captured = captured.min(u64::from(i.snap_len));
                }
                self.data(Packet {
                    interface: 0,
                    link_type: i.link_type,
                    captured: u32::try_from(captured).unwrap_or(u32::MAX),
                    timestamp: None,
                })
            }
            State::Tail => {
                let (_, length, offset) = self.block;
                let trailing = o.u32(b, 0);
                if trailing != length {
                    return Err(PcapError::TrailingLength {
                        offset,
                        length,
                        trailing,
                    });
                }
                self.next(State::BlockHead, 8);
                Ok(None)
            }
        }
    }

    fn magic(&mut self, b: &[u8]) -> Result<Option<PcapEvent>, PcapError> {
        let flavor = Flavor::detect(b).ok_or(PcapError::NotPcap)?;
        self.flavor = Some(flavor);
        if flavor == Flavor::PcapNg {
            // The magic is the Section Header Block's type: keep it.
            self.have = 4;
            self.next(State::BlockHead, 8);
            return Ok(None);
        }
        let le = b.first().is_some_and(|&x| x == 0xD4 || x == 0x4D);
        self.order = if le { Order::Little } else { Order::Big };
        self.next(State::PcapHeader, 20);
        Ok(None)
    }

    /// A pcap record header's packet (its time, its length checked).
    fn record(&self, b: &[u8]) -> Result<Packet, PcapError> {
        let o = self.order;
        let captured = o.u32(b, 8);
        if captured > MAX_RECORD {
            return Err(PcapError::RecordLength { length: captured });
        }
        let link = self.interfaces.first().copied().unwrap_or(NO_INTERFACE);
        let frac = u64::from(o.u32(b, 4));
        let seconds = u64::from(o.u32(b, 0));
        let timestamp = if link.resolution == 9 {
            micros_of(seconds, (frac + 500) / 1000)
        } else {
            micros_of(seconds, frac)
        };
        Ok(Packet {
            interface: 0,
            link_type: link.link_type,
            captured,
            timestamp,
        })
    }

    /// Keeps the block's type, length and start; checks the length.
    fn start_block(&mut self, block_type: u32, length: u32, offset: u64) -> Result<(), PcapError> {
        self.block = (block_type, length, offset);
        if !block_length_ok(length) {
            return Err(PcapError::BlockLength { offset, length });
        }
        self.left = u64::from(length) - 8;
        Ok(())
    }

    fn block_head(&mut self, b: &[u8]) -> Result<Option<PcapEvent>, PcapError> {
        let block_type = self.order.u32(b, 0);
        if block_type == SHB {
            // The length's byte order comes after it: keep both.
            self.have = 8;
            self.next(State::ShbMagic, 12);
            return Ok(None);
        }
        let offset = self.offset.saturating_sub(8);
        self.start_block(block_type, self.order.u32(b, 4), offset)?;
        match block_type {
            IDB => self.field(State::Idb, 8)?,
            EPB | PB => self.field(State::PacketHead(block_type), 20)?,
            SPB => self.field(State::SpbHead, 4)?,
            _ => self.skip_to_tail(),
        }
        Ok(None)
    }

    /// The next option of interface `n`, or the block's end.
    fn option(&mut self, n: usize) -> Result<Option<PcapEvent>, PcapError> {
        if self.room().saturating_sub(self.skip) < 4 {
            self.skip = 0;
            self.skip_to_tail();
        } else {
            self.next(State::Option(n), 4);
        }
        Ok(None)
    }

    /// The interface numbered `n` in the section.
    fn described(&self, n: u32) -> Result<Interface, PcapError> {
        let i = usize::try_from(n).unwrap_or(usize::MAX);
        if i >= self.described {
            Err(PcapError::UnknownInterface { interface: n })
        } else {
            self.interfaces
                .get(i)
                .copied()
                .ok_or(PcapError::TooManyInterfaces { interface: n })
        }
    }

    /// The interface numbered `n` in the section; the block skipped when
    /// there is none.
    fn interface(&mut self, n: u32) -> Result<Interface, PcapError> {
        let found = self.described(n);
        if found.is_err() {
            self.skip_to_tail();
        }
        found
    }

    /// Collect the packet's data next (what a frame needs of it).
    fn data(&mut self, packet: Packet) -> Result<Option<PcapEvent>, PcapError> {
        self.next(
            State::Data(packet),
            usize::try_from(packet.captured).unwrap_or(BUF).min(BUF),
        );
        Ok(None)
    }
}

/// A block length pcapng allows (section 3.1: a multiple of 4, at least
/// the 12 bytes of type, length and trailing length), up to [`MAX_BLOCK`].
const fn block_length_ok(length: u32) -> bool {
    length >= 12 && length.is_multiple_of(4) && length <= MAX_BLOCK
}

/// An Enhanced Packet Block's or a Packet Block's interface, time (in
/// its interface's units) and captured length, from its fixed fields
/// (EPB: interface u32; PB: interface u16, drops u16; then the time's
/// high and low words and the captured length).
fn packet_fields(o: Order, block_type: u32, b: &[u8]) -> (u32, u64, u32) {
    let interface = if block_type == EPB {
        o.u32(b, 0)
    } else {
        u32::from(o.u16(b, 0))
    };
    let units = (u64::from(o.u32(b, 4)) << 32) | u64::from(o.u32(b, 8));
    (interface, units, o.u32(b, 12))
}

/// `seconds` and `micros` as a [`Timestamp`], if in its range.
fn micros_of(seconds: u64, micros: u64) -> Option<Timestamp> {
    let us = seconds.checked_mul(1_000_000)?.checked_add(micros)?;
    Some(Timestamp::from_micros(us))
}

/// A pcapng time (`units` of the interface's resolution since the UNIX
/// epoch, plus its offset in seconds) to the nearest microsecond.
pub(super) fn block_time(units: u64, i: Interface) -> Option<Timestamp> {
    if i.resolution == 6 && i.offset == 0 {
        // Microseconds (the default) and no offset: the units as they are.
        return Some(Timestamp::from_micros(units));
    }
    let units = u128::from(units);
    let exp = u32::from(i.resolution & 0x7F);
    let us: u128 = if i.resolution & 0x80 == 0 {
        if exp <= 6 {
            units.checked_mul(10u128.pow(6 - exp))?
        } else {
            match 10u128.checked_pow(exp - 6) {
                Some(d) => (units + d / 2) / d,
                None => 0,
            }
        }
    } else {
        // units < 2^64, so the product is below 2^84 and the sum below
        // 2^127 for any exponent up to 127.
        let scaled = units.checked_mul(1_000_000)?;
        let half = 1u128.checked_shl(exp)? >> 1;
        scaled.checked_add(half)? >> exp
    };
    let offset = i128::from(i.offset).checked_mul(1_000_000)?;
    let total = i128::try_from(us).ok()?.checked_add(offset)?;
    Some(Timestamp::from_micros(u64::try_from(total).ok()?))
}
