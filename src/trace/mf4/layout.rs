//! Where a bus-logging channel group keeps each field of a frame (ASAM
//! MDF 4.1 "Associated Standard: Bus Logging", sections 6.1 and 7.1 for
//! CAN): the channel group holds one composed channel named after its
//! event type (`CAN_DataFrame`, `CAN_RemoteFrame`, `CAN_ErrorFrame`),
//! whose members are named `CAN_DataFrame.ID`, `.IDE`, `.DLC`,
//! `.DataLength`, `.DataBytes`, `.BusChannel`, `.Dir`, `.EDL`, `.BRS`,
//! `.ESI`; their byte offsets count from the record's start (after its
//! record id). The master channel (channel type 2, or 3 virtual, sync
//! type 1 time) gives the time in seconds since the header's start time,
//! through its `##CC` linear conversion when it has one. `DataBytes` may
//! be a variable-length channel (channel type 1, section 5.18.2): its
//! record field is an offset into signal data (a `##SD` chain, or in MDF
//! 4.2 a variable-length channel group of the same data group), where each
//! value is a u32 length and its bytes.

use super::blocks::{block, id, text, Block, Source};
use super::Mf4Error;

/// The event type of a bus-logging channel group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Event {
    /// `CAN_DataFrame`.
    Data,
    /// `CAN_RemoteFrame`.
    Remote,
    /// `CAN_ErrorFrame`.
    Error,
    /// `CAN_OverloadFrame` (or another CAN event): read as an event.
    Other,
}

/// One field of the record: an unsigned integer or bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct Field {
    /// Byte offset in the record (after the record id).
    pub(super) byte: u32,
    /// Bit offset in its first byte (0-7).
    pub(super) bit: u8,
    /// Width in bits.
    pub(super) bits: u32,
    /// Big-endian (Motorola) byte order.
    pub(super) big_endian: bool,
    /// A string (`Tx`/`Rx` for a direction).
    pub(super) text: bool,
}

impl Field {
    /// Its bytes in `record`, when they lie inside it.
    pub(super) fn bytes<'r>(&self, record: &'r [u8]) -> Option<&'r [u8]> {
        let start = self.byte as usize;
        let len = (self.bits as usize).div_ceil(8);
        record.get(start..start.checked_add(len)?)
    }

    /// Its value as an unsigned integer (at most 64 bits), when it lies
    /// inside `record`.
    #[inline]
    pub(super) fn uint(&self, record: &[u8]) -> Option<u64> {
        if self.bit == 0 && !self.big_endian {
            // Whole little-endian bytes, as bus logging writes its fields.
            let at = record.get(self.byte as usize..)?;
            match self.bits {
                8 => return at.first().map(|&b| u64::from(b)),
                16 => return at.first_chunk().map(|b| u64::from(u16::from_le_bytes(*b))),
                32 => return at.first_chunk().map(|b| u64::from(u32::from_le_bytes(*b))),
                64 => return at.first_chunk().map(|b| u64::from_le_bytes(*b)),
                _ => {}
            }
        }
        self.bits_of(record)
    }

    /// [`uint`](Self::uint) of any bit offset, width and byte order.
    #[inline(never)]
    fn bits_of(&self, record: &[u8]) -> Option<u64> {
        if self.bits == 0 || self.bits > 64 {
            return None;
        }
        let width = (u32::from(self.bit) + self.bits).div_ceil(8) as usize;
        let start = self.byte as usize;
        let bytes = record.get(start..start.checked_add(width)?)?;
        let mut v: u128 = 0;
        if self.big_endian {
            for &b in bytes {
                v = v << 8 | u128::from(b);
            }
            let tail = width as u32 * 8 - u32::from(self.bit) - self.bits;
            v >>= tail;
        } else {
            for &b in bytes.iter().rev() {
                v = v << 8 | u128::from(b);
            }
            v >>= self.bit;
        }
        let mask = if self.bits == 64 {
            u128::from(u64::MAX)
        } else {
            (1u128 << self.bits) - 1
        };
        u64::try_from(v & mask).ok()
    }
}

/// How a record's time is read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Time {
    /// A float (32 or 64 bits, little- or big-endian) or an unsigned
    /// integer, then `offset + factor * raw` seconds.
    Channel {
        /// The field.
        field: Field,
        /// An IEEE 754 float (else an unsigned integer).
        float: bool,
        /// The linear conversion's offset (P1).
        offset: f64,
        /// The linear conversion's factor (P2).
        factor: f64,
    },
    /// A virtual master: the record's index through the conversion.
    Index {
        /// The conversion's offset.
        offset: f64,
        /// The conversion's factor.
        factor: f64,
    },
    /// No time channel.
    None,
}

/// A bus-logging channel group's fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Layout {
    pub(super) event: Event,
    pub(super) time: Time,
    pub(super) id: Option<Field>,
    pub(super) ide: Option<Field>,
    pub(super) dlc: Option<Field>,
    pub(super) data_length: Option<Field>,
    pub(super) data_bytes: Option<Field>,
    /// `DataBytes` as a variable-length channel (channel type 1): the
    /// record holds an offset (its field) into the signal data its
    /// `cn_data` links (a `##SD` chain, or a variable-length channel
    /// group of the same data group).
    pub(super) vlsd: Option<(Field, u64)>,
    pub(super) bus_channel: Option<Field>,
    pub(super) dir: Option<Field>,
    pub(super) edl: Option<Field>,
}

/// The most channels read in one channel group (members included).
const MAX_CHANNELS: usize = 4096;

/// The bus-logging layout of the channel group `cg`, `None` when it is
/// not a CAN bus-logging group (no `CAN_` event channel). `hops` counts
/// the blocks left to visit against link cycles.
pub(super) fn layout(
    src: &mut dyn Source,
    cg: &Block,
    hops: &mut u64,
) -> Result<Option<Layout>, Mf4Error> {
    let mut l = Layout {
        event: Event::Other,
        time: Time::None,
        id: None,
        ide: None,
        dlc: None,
        data_length: None,
        data_bytes: None,
        vlsd: None,
        bus_channel: None,
        dir: None,
        edl: None,
    };
    let mut event = None;
    // Channels to visit: the group's first, and the members' first of
    // each composed channel met (one level, as bus logging uses).
    let mut pending = [cg.link(1), 0];
    let mut seen = 0usize;
    for level in 0..2 {
        let mut at = pending.get(level).copied().unwrap_or(0);
        while at != 0 {
            *hops = hops
                .checked_sub(1)
                .ok_or(Mf4Error::LinkCycle { what: "channel" })?;
            seen += 1;
            if seen > MAX_CHANNELS {
                return Err(Mf4Error::LinkCycle { what: "channel" });
            }
            let cn = block(src, at, &[id::CN])?;
            let name = text(src, cn.link(2)).unwrap_or_default();
            let name = name.as_str();
            let (prefix, member) = match name.rsplit_once('.') {
                Some((p, m)) => (p, m),
                None => (name, ""),
            };
            if let Some(kind) = event_of(prefix) {
                event = event.or(Some(kind));
            }
            let composition = cn.link(1);
            if level == 0 && composition != 0 && event_of(name).is_some() {
                if let Some(slot) = pending.get_mut(1) {
                    *slot = composition;
                }
            }
            let channel_type = cn.u8(0);
            let sync = cn.u8(1);
            if (channel_type == 2 || channel_type == 3) && sync == 1 {
                l.time = time(src, &cn, at)?;
            } else if event_of(prefix).is_some() {
                let f = field(&cn);
                let slot = match member {
                    "ID" => &mut l.id,
                    "IDE" => &mut l.ide,
                    "DLC" => &mut l.dlc,
                    "DataLength" => &mut l.data_length,
                    "DataBytes" => &mut l.data_bytes,
                    "BusChannel" => &mut l.bus_channel,
                    "Dir" => &mut l.dir,
                    "EDL" => &mut l.edl,
                    _ => &mut None,
                };
                if slot.is_none() && channel_type == 0 {
                    *slot = Some(f);
                } else if member == "DataBytes" && channel_type == 1 && l.vlsd.is_none() {
                    l.vlsd = Some((f, cn.link(5)));
                }
            }
            at = cn.link(0);
        }
    }
    Ok(event.map(|event| Layout { event, ..l }))
}

/// The event type a channel name (or its prefix) names.
fn event_of(name: &str) -> Option<Event> {
    match name {
        "CAN_DataFrame" => Some(Event::Data),
        "CAN_RemoteFrame" => Some(Event::Remote),
        "CAN_ErrorFrame" => Some(Event::Error),
        n if n.starts_with("CAN_") && !n.contains('.') => Some(Event::Other),
        _ => None,
    }
}

/// A channel's place in the record.
fn field(cn: &Block) -> Field {
    let data_type = cn.u8(2);
    Field {
        byte: cn.u32(4),
        bit: cn.u8(3) & 7,
        bits: cn.u32(8),
        big_endian: matches!(data_type, 1 | 3 | 5),
        text: matches!(data_type, 6 | 7),
    }
}

/// The master channel `cn` (at `at`) as a time.
fn time(src: &mut dyn Source, cn: &Block, at: u64) -> Result<Time, Mf4Error> {
    let (offset, factor) = match cn.link(4) {
        0 => (0.0, 1.0),
        cc_at => {
            let cc = block(src, cc_at, &[id::CC])?;
            match cc.u8(0) {
                0 => (0.0, 1.0),
                1 => (cc.f64(24), cc.f64(32)),
                conversion => {
                    return Err(Mf4Error::TimeConversion {
                        at: cc_at,
                        conversion,
                    })
                }
            }
        }
    };
    if cn.u8(0) == 3 {
        return Ok(Time::Index { offset, factor });
    }
    let f = field(cn);
    let float = match cn.u8(2) {
        0 | 1 => false,
        4 | 5 if f.bits == 32 || f.bits == 64 => true,
        data_type => return Err(Mf4Error::TimeType { at, data_type }),
    };
    Ok(Time::Channel {
        field: f,
        float,
        offset,
        factor,
    })
}

impl Time {
    /// The time of a record (`index` counts the group's records from 0)
    /// in seconds, when it has one.
    pub(super) fn seconds(&self, record: &[u8], index: u64) -> Option<f64> {
        let (raw, offset, factor) = match *self {
            Time::Channel {
                field,
                float,
                offset,
                factor,
            } => {
                let raw = field.uint(record)?;
                let raw = match (float, field.bits) {
                    (true, 32) => f64::from(f32::from_bits(raw as u32)),
                    (true, _) => f64::from_bits(raw),
                    (false, _) => raw as f64,
                };
                (raw, offset, factor)
            }
            Time::Index { offset, factor } => (index as f64, offset, factor),
            Time::None => return None,
        };
        let s = offset + factor * raw;
        s.is_finite().then_some(s)
    }
}
