//! The bits a frame occupies on the bus, for the bus load
//! ([`crate::log::bus_load`]): classic data and remote frames, CAN FD
//! frames (their arbitration and data phases apart, the data phase at the
//! data bit rate when the frame's BRS is set) and error frames.
//!
//! ## Classic frames
//!
//! A classic data or remote frame (ISO 11898-1:2015 section 10.4 "Frame
//! formats"; Bosch CAN Specification 2.0 part B section 3.1 "Frame
//! types") occupies, before stuffing:
//!
//! | field | base (11-bit) | extended (29-bit) |
//! |---|---|---|
//! | start of frame | 1 | 1 |
//! | arbitration | identifier 11, RTR 1 | identifier 11, SRR 1, IDE 1, identifier 18, RTR 1 |
//! | control | IDE 1, r0 1, DLC 4 | r1 1, r0 1, DLC 4 |
//! | data | 8 per byte (none in a remote frame) | 8 per byte |
//! | CRC | sequence 15, delimiter 1 | 15, 1 |
//! | ACK | slot 1, delimiter 1 | 1, 1 |
//! | end of frame | 7 | 7 |
//! | intermission (interframe space) | 3 | 3 |
//! | **total** | **47 + 8n** | **67 + 8n** |
//!
//! Bit stuffing (CAN 2.0 part B section 5 "Bit stuffing"; ISO 11898-1
//! section 10.5) covers start of frame through the CRC sequence (34 + 8n
//! bits in a base frame, 54 + 8n in an extended one): after five equal bits
//! the transmitter inserts one of the opposite value, which counts in the
//! next run. The worst case is one stuff bit per four bits after the first,
//! floor((g - 1) / 4) for g stuffed bits (Davis, Burns, Bril and Lukkien,
//! "Controller Area Network (CAN) schedulability analysis: refuted,
//! revisited and revised", Real-Time Systems 35(3), 2007, section 3).
//!
//! The load uses the **exact stuffed count**: the
//! frame's bits are laid out, its CRC-15 computed (generator
//! x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1, ISO 11898-1 section
//! 10.4.2.6), and the stuff bits counted; the loads of the unstuffed and
//! the worst-case counts are given beside it as bounds. For a few frames
//! (n data bytes, g stuffed bits):
//!
//! | frame | unstuffed | g | worst case | exact |
//! |---|---|---|---|---|
//! | base, 0 bytes: `000#` | 47 | 34 | 47 + 8 = 55 | 47 + 6 = 53 |
//! | base remote, DLC 0: `000#R` | 47 | 34 | 55 | 47 + 3 = 50 |
//! | base, 8 bytes: `6F8#FF000CFE00000000` | 111 | 98 | 111 + 24 = 135 | 124 |
//! | extended, 8 bytes: `18EBFF00#01A00FA6603BD140` | 131 | 118 | 131 + 29 = 160 | 141 |
//!
//! By hand: `000#` is 34 dominant bits (start of frame, identifier, RTR,
//! IDE, r0 and DLC are 19, and the CRC-15 of an all-dominant input is 0:
//! 15 more); a recessive stuff bit follows every fifth, 6 in all. `000#R`
//! is 12 dominant bits (stuff bits after the 5th and the 10th), a recessive
//! RTR, 6 dominant bits (IDE, r0, DLC: a stuff bit after the 5th), then the
//! CRC `111001111000101` (73C5h), whose longest run is 4: 3 stuff bits.
//! The two 8-byte frames are from python-can's test log `logfile.asc`,
//! written by Vector CANoe, whose `BitCount` column (intermission
//! included) gives 124 and 141; this module's count agrees with CANoe's
//! for five of that log's six frames (for the sixth, `6F9#050C000000000000`,
//! CANoe counts one bit more than the 123 computed here). The tests check
//! these counts, and that every frame's exact count lies between its
//! unstuffed and worst-case counts.
//!
//! ## CAN FD frames
//!
//! A CAN FD frame (ISO 11898-1:2015 section 10.4.2, FD base and FD
//! extended formats) has no remote form; n is its data length (0 to 8, 12,
//! 16, 20, 24, 32, 48 or 64 bytes). Its **arbitration phase** runs at the
//! nominal bit rate up to the BRS bit, its **data phase** from BRS's sample
//! point to the CRC delimiter at the data bit rate when BRS is set (at the
//! nominal rate when it is not), the rest at the nominal rate again:
//!
//! | phase | field | base (11-bit) | extended (29-bit) |
//! |---|---|---|---|
//! | arbitration | start of frame | 1 | 1 |
//! | | identifier and its bits | identifier 11, RRS 1, IDE 1 | identifier 11, SRR 1, IDE 1, identifier 18, RRS 1 |
//! | | FDF, res, BRS | 3 | 3 |
//! | data | ESI, DLC | 1 + 4 | 1 + 4 |
//! | | data | 8n | 8n |
//! | | CRC field, n <= 16 | stuff count 4 (3 Gray-coded + parity), CRC-17, 6 fixed stuff bits: 27 | 27 |
//! | | CRC field, n > 16 | 4, CRC-21, 7 fixed stuff bits: 32 | 32 |
//! | tail | CRC delimiter, ACK slot and delimiter, end of frame, intermission | 1 + 2 + 7 + 3 = 13 | 13 |
//! | | **total** (n <= 16, n > 16) | **62 + 8n, 67 + 8n** | **81 + 8n, 86 + 8n** |
//!
//! The fixed stuff bits of the CRC field (ISO 11898-1:2015 section 10.5)
//! are one before the stuff count and one after every 4 bits of the stuff
//! count and CRC sequence: ceil(21 / 4) = 6 with a CRC-17, ceil(25 / 4) = 7
//! with a CRC-21. Dynamic stuffing (one stuff bit after five equal bits)
//! covers start of frame to the end of the data field only, g = 22 + 8n
//! bits in a base frame and 41 + 8n in an extended one; the first fixed
//! stuff bit takes the place of a dynamic stuff bit due after the last data
//! bit. So the frame has, beside the bits above: none in the unstuffed
//! count; floor((g - 1) / 4) in the worst case, floor((a - 1) / 4) of them
//! in the arbitration phase (a = 17 or 36 bits, start of frame to BRS) and
//! the others in the data phase (the worst case for the time as well: the
//! data phase is never slower than the arbitration phase); and in the exact
//! count, those the frame's bits need, counted as for a classic frame (ESI
//! as the trace gives it, dominant when it does not), a stuff bit that
//! follows BRS being in the data phase. The CRC does not change the count
//! (its field has fixed stuff bits only), so it is not computed.
//!
//! | frame | phase | unstuffed | worst case |
//! |---|---|---|---|
//! | `123##0` + 8 bytes (no BRS) | all nominal | 62 + 64 = 126 | 126 + floor(85 / 4) = 147 |
//! | `123##1` + 64 bytes | arbitration + tail; data | 17 + 13 = 30; 5 + 512 + 32 = 549 | 30 + 4 = 34; 549 + 129 = 678 |
//! | `12345678##1` + 12 bytes | arbitration + tail; data | 36 + 13 = 49; 5 + 96 + 27 = 128 | 49 + 8 = 57; 128 + 26 = 154 |
//!
//! ## Error frames
//!
//! An error frame (ISO 11898-1:2015 section 10.4.4) is an error flag of 6
//! bits, the other nodes' error flags superposed on it (0 to 6 bits more),
//! the error delimiter (8) and the intermission (3): 17 to 23 bits at the
//! nominal rate. The trace does not tell the superposition: the unstuffed
//! and the exact counts take none (17 bits: every node flags the error at
//! once, as when all see the same stuff or form error), the worst case
//! takes 6 (23 bits). The frame it destroyed is not in the trace, so its
//! bits up to the error are not counted.
//!

use crate::trace::FdFrame;
use crate::{CanFrame, CanId};

/// The intermission after every frame (bits).
pub const INTERMISSION: u32 = 3;
/// An error frame's bits without superposed error flags: error flag 6,
/// delimiter 8, intermission 3.
pub const ERROR_FRAME: u32 = 6 + 8 + INTERMISSION;
/// The most error flag bits superposed on an error frame's own.
pub const ERROR_SUPERPOSITION: u32 = 6;
/// The CRC-15 generator polynomial of CAN (without its x^15 term).
pub(crate) const CRC15_POLY: u16 = 0x4599;

/// Bits counted three ways: without stuff bits, with those the frame's
/// bits need, with the most a frame of its shape can have.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Without stuff bits (intermission included).
    pub unstuffed: u32,
    /// With the stuff bits this frame's bits need.
    pub stuffed: u32,
    /// With the most stuff bits.
    pub worst_case: u32,
}

impl Counts {
    /// `unstuffed` bits of which at most `worst` are stuff bits, `stuff`
    /// of them exactly.
    const fn new(unstuffed: u32, stuff: u32, worst: u32) -> Counts {
        Counts {
            unstuffed,
            stuffed: unstuffed.saturating_add(stuff),
            worst_case: unstuffed.saturating_add(worst),
        }
    }
}

/// The bits one frame occupies: those at the nominal bit rate and those
/// at the data bit rate (the data phase of a CAN FD frame whose BRS is
/// set; none for any other frame).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameBits {
    /// At the nominal bit rate.
    pub nominal: Counts,
    /// At the data bit rate.
    pub data: Counts,
}

impl FrameBits {
    /// The bits of a classic `frame` (see the module's table).
    #[must_use]
    pub fn of(frame: &CanFrame) -> FrameBits {
        FrameBits::with_stuff(frame, stuff_bits(frame))
    }

    /// The bits of a classic `frame` whose stuff bits are `stuff`.
    pub(crate) fn with_stuff(frame: &CanFrame, stuff: u32) -> FrameBits {
        let extended = frame.id().is_extended();
        let g = stuffed_field_bits(extended, data_bytes(frame));
        // CRC delimiter, ACK slot and delimiter, end of frame, intermission.
        let unstuffed = g + 1 + 2 + 7 + INTERMISSION;
        FrameBits {
            nominal: Counts::new(unstuffed, stuff, (g - 1) / 4),
            data: Counts::default(),
        }
    }

    /// The bits of a CAN FD frame (see the module's table).
    #[must_use]
    pub fn of_fd(frame: &FdFrame) -> FrameBits {
        let (bits, arbitration) = fd_header(frame);
        let mut runs = Runs::default();
        runs.push(bits >> (fd_header_len(frame) - arbitration), arbitration);
        // A stuff bit after BRS is sent in the data phase.
        let stuff_arbitration = runs.stuff.saturating_sub(u32::from(runs.ended_with_stuff));
        runs.push(bits, fd_header_len(frame) - arbitration);
        for chunk in frame.data().chunks(16) {
            let mut value = 0u128;
            for &byte in chunk {
                value = value << 8 | u128::from(byte);
            }
            runs.push(value, 8 * chunk.len() as u32);
        }
        // The first fixed stuff bit takes the place of one due at the end.
        let stuff = runs.stuff.saturating_sub(u32::from(runs.ended_with_stuff));
        let n = frame.data().len() as u32;
        let g = fd_header_len(frame) + 8 * n;
        let worst = (g - 1) / 4;
        let worst_arbitration = (arbitration - 1) / 4;
        // Stuff count 4, the CRC and the fixed stuff bits.
        let crc_field = if n <= 16 { 4 + 17 + 6 } else { 4 + 21 + 7 };
        let data_unstuffed = g - arbitration + crc_field;
        let tail = 1 + 2 + 7 + INTERMISSION;
        let arbitration_bits =
            Counts::new(arbitration + tail, stuff_arbitration, worst_arbitration);
        let data_bits = Counts::new(
            data_unstuffed,
            stuff.saturating_sub(stuff_arbitration),
            worst - worst_arbitration,
        );
        if frame.brs() {
            FrameBits {
                nominal: arbitration_bits,
                data: data_bits,
            }
        } else {
            FrameBits {
                nominal: Counts {
                    unstuffed: arbitration_bits.unstuffed + data_bits.unstuffed,
                    stuffed: arbitration_bits.stuffed + data_bits.stuffed,
                    worst_case: arbitration_bits.worst_case + data_bits.worst_case,
                },
                data: Counts::default(),
            }
        }
    }

    /// The bits of an error frame (see the module's doc): 17, 17 and 23.
    #[must_use]
    pub const fn error_frame() -> FrameBits {
        FrameBits {
            nominal: Counts::new(ERROR_FRAME, 0, ERROR_SUPERPOSITION),
            data: Counts {
                unstuffed: 0,
                stuffed: 0,
                worst_case: 0,
            },
        }
    }

    /// Every bit, at either rate.
    #[must_use]
    pub const fn total(&self) -> Counts {
        Counts {
            unstuffed: self.nominal.unstuffed.saturating_add(self.data.unstuffed),
            stuffed: self.nominal.stuffed.saturating_add(self.data.stuffed),
            worst_case: self.nominal.worst_case.saturating_add(self.data.worst_case),
        }
    }
}

/// The bits of a classic frame before stuffing that are covered by
/// stuffing (start of frame to the end of the CRC sequence).
const fn stuffed_field_bits(extended: bool, data_bytes: u32) -> u32 {
    (if extended { 54 } else { 34 }) + 8 * data_bytes
}

/// A classic frame's data bytes on the bus: none in a remote frame.
fn data_bytes(frame: &CanFrame) -> u32 {
    if frame.is_remote() {
        0
    } else {
        u32::try_from(frame.data().len()).unwrap_or(8)
    }
}

/// The stuff bits a classic `frame` needs: its bits from start of frame to
/// the end of the CRC sequence laid out, the CRC-15 computed over start of
/// frame to the data, and one stuff bit counted after every five equal
/// bits.
///
/// The bits (at most 118: an extended 8-byte frame) are one `u128`; the
/// CRC goes a byte at a time through a table (zero bits in front of the
/// message leave a CRC that starts at 0 unchanged, so the message is
/// padded to whole bytes), and the stuffing is counted a run of equal bits
/// at a time (a run of e bits holds floor(e / 5) stuff bits). The tests
/// check it against a bit-by-bit count of the same rules on every frame
/// shape.
#[must_use]
pub fn stuff_bits(frame: &CanFrame) -> u32 {
    let (mut bits, mut len) = header(frame);
    if !frame.is_remote() {
        for &byte in frame.data() {
            bits = bits << 8 | u128::from(byte);
            len += 8;
        }
    }
    // The message in whole bytes, most significant first.
    let bytes = len.div_ceil(8);
    let mut crc: u16 = 0;
    for k in (0..bytes).rev() {
        let byte = (bits.checked_shr(8 * k).unwrap_or(0) & 0xFF) as u8;
        let index = usize::from((crc >> 7) as u8 ^ byte);
        crc = (crc << 8 ^ CRC15_TABLE.get(index).copied().unwrap_or(0)) & 0x7FFF;
    }
    let bits = bits << 15 | u128::from(crc);
    let mut runs = Runs::default();
    runs.push(bits, len + 15);
    runs.stuff
}

/// Start of frame, arbitration and control fields of a classic frame as
/// bits (the last one lowest) and their number.
fn header(frame: &CanFrame) -> (u128, u32) {
    let rtr = u128::from(frame.is_remote());
    let dlc = u128::from(frame.dlc() & 0xF);
    match frame.id() {
        // SOF 0, identifier 11, RTR, IDE 0, r0 0, DLC 4.
        CanId::Standard(id) => ((u128::from(id) << 1 | rtr) << 6 | dlc, 19),
        // SOF 0, identifier 11, SRR 1, IDE 1, identifier 18, RTR, r1 0,
        // r0 0, DLC 4.
        CanId::Extended(id) => {
            let base = u128::from(id >> 18) << 2 | 0b11;
            let ext = (base << 18 | u128::from(id & 0x3_FFFF)) << 1 | rtr;
            (ext << 6 | dlc, 39)
        }
    }
}

/// The bits of a CAN FD frame from start of frame to its DLC, and the
/// arbitration phase's share of them (start of frame to BRS).
fn fd_header(frame: &FdFrame) -> (u128, u32) {
    let brs = u128::from(frame.brs());
    let esi = u128::from(frame.esi());
    // FDF 1, res 0, BRS; then ESI and DLC.
    let control = |bits: u128| {
        ((((bits << 2 | 0b10) << 1 | brs) << 1 | esi) << 4) | u128::from(frame.dlc() & 0xF)
    };
    match frame.id() {
        // SOF 0, identifier 11, RRS 0, IDE 0.
        CanId::Standard(id) => (control(u128::from(id) << 2), 17),
        // SOF 0, identifier 11, SRR 1, IDE 1, identifier 18, RRS 0.
        CanId::Extended(id) => {
            let base = u128::from(id >> 18) << 2 | 0b11;
            (control((base << 18 | u128::from(id & 0x3_FFFF)) << 1), 36)
        }
    }
}

/// [`fd_header`]'s bits: 22 or 41.
fn fd_header_len(frame: &FdFrame) -> u32 {
    if frame.id().is_extended() {
        41
    } else {
        22
    }
}

/// Bit stuffing counted a run of equal bits at a time, over bits fed in
/// pieces: a run of e bits, counting a stuff bit of the same value just
/// before it, holds floor(e / 5) stuff bits, and when e is a multiple of 5
/// its last stuff bit starts the next run.
#[derive(Clone, Copy, Debug, Default)]
struct Runs {
    /// The value of the last bit sent (stuff bits included) and how many
    /// equal ones end the bits so far.
    value: bool,
    len: u32,
    stuff: u32,
    /// The last bit sent is a stuff bit.
    ended_with_stuff: bool,
}

impl Runs {
    /// The `len` low bits of `bits`, sent highest first.
    fn push(&mut self, bits: u128, len: u32) {
        let Some(mut s) = bits.checked_shl(128u32.saturating_sub(len)) else {
            return;
        };
        let mut left = len.min(128);
        while left > 0 {
            let ones = s >> 127 == 1;
            let run = if ones { !s } else { s }.leading_zeros().min(left);
            let e = run + if ones == self.value { self.len } else { 0 };
            self.stuff += e / 5;
            self.ended_with_stuff = e % 5 == 0;
            (self.value, self.len) = if self.ended_with_stuff {
                (!ones, 1)
            } else {
                (ones, e % 5)
            };
            s = s.checked_shl(run).unwrap_or(0);
            left -= run;
        }
    }
}

/// CRC-15 of CAN one byte at a time: entry i is the register after the 8
/// bits of i entered a register of `i << 7`.
const CRC15_TABLE: [u16; 256] = crate::sdo::crc::msb_first_table(15, CRC15_POLY);
