//! One packet of `LINKTYPE_CAN_SOCKETCAN` (tcpdump.org's link-layer header
//! type registry, entry 227): the Linux `struct can_frame` /
//! `struct canfd_frame`, its identifier word in network byte order.

use super::{PcapError, PcapEvent, PcapFrame, LINKTYPE_CAN_SOCKETCAN};
use crate::clock::Timestamp;
use crate::frame::{CanFrame, CanId};
use crate::trace::{FdFrame, OnBus, Unsupported};

/// A packet whose data is being collected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Packet {
    pub(super) interface: u32,
    pub(super) link_type: u16,
    pub(super) captured: u32,
    pub(super) timestamp: Option<Timestamp>,
}

/// Bit 31 of the identifier word: a 29-bit identifier (`CAN_EFF_FLAG`).
const EFF: u32 = 0x8000_0000;
/// Bit 30: a remote frame (`CAN_RTR_FLAG`).
const RTR: u32 = 0x4000_0000;
/// Bit 29: an error frame (`CAN_ERR_FLAG`).
const ERR: u32 = 0x2000_0000;
/// The identifier bits.
const ID: u32 = 0x1FFF_FFFF;
/// FD flags bit 2: a CAN FD frame (`CANFD_FDF`).
const FDF: u8 = 0x04;
/// Bit 7 of the fifth byte: a CAN XL frame (`CANXL_XLF`).
const XLF: u8 = 0x80;
/// Identifier word, payload length, FD flags, two reserved bytes.
const HEADER: usize = 8;
/// A `struct canfd_frame`: what older writers give every CAN FD frame.
const CANFD_FRAME: u32 = 72;

/// The event of one packet; `data` is what was kept of its captured bytes
/// (the first 96 or fewer).
pub(super) fn event(packet: Packet, data: &[u8]) -> Result<PcapEvent, PcapError> {
    let on_bus = |what, on_bus| PcapEvent::Unsupported {
        what,
        link_type: packet.link_type,
        timestamp: packet.timestamp,
        on_bus,
    };
    let unsupported = |what| on_bus(what, None);
    if packet.link_type != LINKTYPE_CAN_SOCKETCAN {
        return Ok(unsupported(Unsupported::LinkType));
    }
    let too_short = PcapError::SocketCanTooShort {
        captured: packet.captured,
    };
    let (Some(word), Some(&length), Some(&fd_flags)) = (
        data.get(..4).and_then(|w| <[u8; 4]>::try_from(w).ok()),
        data.get(4),
        data.get(5),
    ) else {
        return Err(too_short);
    };
    if length & XLF != 0 {
        return Ok(unsupported(Unsupported::CanXl));
    }
    let word = u32::from_be_bytes(word);
    if word & ERR != 0 {
        return Ok(on_bus(Unsupported::ErrorFrame, Some(OnBus::ErrorFrame)));
    }
    let raw = word & ID;
    let id = if word & EFF != 0 {
        CanId::extended(raw)
    } else {
        u16::try_from(raw).ok().and_then(CanId::standard)
    };
    if fd_flags & FDF != 0 || packet.captured == CANFD_FRAME || length > 8 {
        // The frame for the bus load when its identifier and data are
        // whole (FD flags: bit 0 BRS, bit 1 ESI).
        let fd = id.and_then(|id| {
            let payload = data.get(HEADER..HEADER + usize::from(length))?;
            FdFrame::new(id, payload, fd_flags & 1 != 0, fd_flags & 2 != 0)
        });
        return Ok(on_bus(Unsupported::CanFd, fd.map(OnBus::Fd)));
    }
    let id = id.ok_or(PcapError::BadId { raw })?;
    let frame = if word & RTR != 0 {
        CanFrame::remote(id, length)
    } else {
        let payload = data
            .get(HEADER..HEADER + usize::from(length))
            .ok_or(too_short)?;
        CanFrame::new(id, payload)
    }
    .map_err(|_| PcapError::PayloadLength { length })?;
    Ok(PcapEvent::Frame(PcapFrame {
        timestamp: packet.timestamp,
        interface: packet.interface,
        frame,
    }))
}
