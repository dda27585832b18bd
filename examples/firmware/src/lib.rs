//! The hardware side of the footprint firmware: a memory-mapped CAN
//! mailbox and a free-running microsecond timer, read and written with
//! volatile accesses (no HAL, nothing board-specific), and a panic handler
//! that pulls in no formatting.
//!
//! The register block is a made-up but typical one (one receive and one
//! transmit mailbox of five 32-bit words each); the addresses sit in the
//! Cortex-M peripheral region. A port to a real part replaces only this
//! file. The library itself forbids `unsafe`; the few volatile accesses
//! below are the firmware's, each one a register of the block described
//! here.

#![no_std]

use core::panic::PanicInfo;
use core::ptr::{read_volatile, write_volatile};

use canopen_codec::machine::Machine;
use canopen_codec::{CanFrame, CanId, Timestamp};

pub mod mem;

/// Base address of the CAN mailbox block.
const CAN_BASE: usize = 0x4000_6400;
/// Receive mailbox: status (bit 0: a frame is waiting; write 1 to release).
const RX_STATUS: usize = CAN_BASE;
/// Receive mailbox: identifier (bits 0-28), bit 30 remote, bit 31 extended.
const RX_ID: usize = CAN_BASE + 0x04;
/// Receive mailbox: DLC (bits 0-3).
const RX_DLC: usize = CAN_BASE + 0x08;
/// Receive mailbox: data bytes 0-3 (little-endian).
const RX_DATA_LO: usize = CAN_BASE + 0x0C;
/// Receive mailbox: data bytes 4-7.
const RX_DATA_HI: usize = CAN_BASE + 0x10;
/// Transmit mailbox: status (bit 0: free; write 1 to request transmission).
const TX_STATUS: usize = CAN_BASE + 0x20;
/// Transmit mailbox: identifier, as [`RX_ID`].
const TX_ID: usize = CAN_BASE + 0x24;
/// Transmit mailbox: DLC.
const TX_DLC: usize = CAN_BASE + 0x28;
/// Transmit mailbox: data bytes 0-3.
const TX_DATA_LO: usize = CAN_BASE + 0x2C;
/// Transmit mailbox: data bytes 4-7.
const TX_DATA_HI: usize = CAN_BASE + 0x30;
/// A free-running 32-bit counter at 1 MHz.
const TIMER_COUNT: usize = 0x4000_0024;

const ID_EXTENDED: u32 = 1 << 31;
const ID_REMOTE: u32 = 1 << 30;
const ID_MASK: u32 = 0x1FFF_FFFF;

/// Reads the 32-bit register at `addr`.
fn read(addr: usize) -> u32 {
    // SAFETY: `addr` is one of the aligned 32-bit registers of the block
    // above; a volatile read is how MMIO is read.
    unsafe { read_volatile(addr as *const u32) }
}

/// Writes the 32-bit register at `addr`.
fn write(addr: usize, value: u32) {
    // SAFETY: as in `read`.
    unsafe { write_volatile(addr as *mut u32, value) }
}

/// Reads one peripheral register at `addr` (the application's sensors).
#[must_use]
pub fn read_register(addr: usize) -> u32 {
    read(addr)
}

/// Writes one peripheral register at `addr` (the application's outputs).
pub fn write_register(addr: usize, value: u32) {
    write(addr, value);
}

/// The CAN controller's mailboxes.
#[derive(Debug, Default)]
pub struct Can;

impl Can {
    /// The frame waiting in the receive mailbox, if any (released).
    pub fn receive(&mut self) -> Option<CanFrame> {
        if read(RX_STATUS) & 1 == 0 {
            return None;
        }
        let raw_id = read(RX_ID);
        let dlc = (read(RX_DLC) & 0xF) as u8;
        let lo = read(RX_DATA_LO).to_le_bytes();
        let hi = read(RX_DATA_HI).to_le_bytes();
        write(RX_STATUS, 1);
        let id = if raw_id & ID_EXTENDED != 0 {
            CanId::extended(raw_id & ID_MASK)?
        } else {
            CanId::standard((raw_id & 0x7FF) as u16)?
        };
        if raw_id & ID_REMOTE != 0 {
            return CanFrame::remote(id, dlc).ok();
        }
        let data = [lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]];
        let len = usize::from(dlc.min(8));
        CanFrame::new(id, data.get(..len)?).ok()
    }

    /// Sends `frame` (waits for the transmit mailbox to be free).
    pub fn transmit(&mut self, frame: &CanFrame) {
        while read(TX_STATUS) & 1 == 0 {
            core::hint::spin_loop();
        }
        let id = frame.id();
        let mut raw_id = id.raw();
        if id.is_extended() {
            raw_id |= ID_EXTENDED;
        }
        if frame.is_remote() {
            raw_id |= ID_REMOTE;
        }
        let d = frame.padded_data();
        write(TX_ID, raw_id);
        write(TX_DLC, u32::from(frame.dlc()));
        write(TX_DATA_LO, u32::from_le_bytes([d[0], d[1], d[2], d[3]]));
        write(TX_DATA_HI, u32::from_le_bytes([d[4], d[5], d[6], d[7]]));
        write(TX_STATUS, 1);
    }
}

/// The timer, extended from 32 to 64 bits (call [`Clock::now`] at least
/// once every 71 minutes).
#[derive(Debug, Default)]
pub struct Clock {
    last: u32,
    micros: u64,
}

impl Clock {
    /// The time now.
    pub fn now(&mut self) -> Timestamp {
        let count = read(TIMER_COUNT);
        self.micros = self
            .micros
            .wrapping_add(u64::from(count.wrapping_sub(self.last)));
        self.last = count;
        Timestamp::from_micros(self.micros)
    }
}

/// One turn of the contract loop (`machine::Machine`): the received frame,
/// due timers, then every frame to send. Events are the caller's.
pub fn run_once<M: Machine>(node: &mut M, can: &mut Can, now: Timestamp) {
    if let Some(frame) = can.receive() {
        node.handle_frame(now, &frame);
    }
    if node.poll_timeout().is_some_and(|due| due <= now) {
        node.handle_timeout(now);
    }
    while let Some(frame) = node.poll_transmit() {
        can.transmit(&frame);
    }
}

/// Halts: no message, no formatting code.
#[panic_handler]
fn panic(_info: &PanicInfo) -> ! {
    loop {
        core::hint::spin_loop();
    }
}
