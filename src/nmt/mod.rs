//! NMT module control and NMT error control (heartbeat, boot-up, node
//! guarding), CiA 301.
//!
//! - NMT command, identifier 0x000, 2 bytes: command specifier, target node
//!   (0 = all nodes).
//! - Heartbeat / boot-up / node-guarding reply, identifier 0x700 + node,
//!   1 byte: bit 7 the node-guarding toggle (0 in heartbeats), bits 6-0 the
//!   NMT state (0 = boot-up).
//! - Node-guarding request: a remote frame on 0x700 + node.
//!
//! Unknown command and state values decode to `Unknown(raw)`, never an error.
//! The frames are read and written in one place, the NMT wire layer
//! ([`NmtFrame`] / [`NmtCommand`], [`HeartbeatFrame`] / [`Heartbeat`],
//! [`guard_request`]), through the crate's one codec shape
//! ([`Codec`](crate::wire::Codec)).

use core::fmt;

pub mod guarding;
pub mod heartbeat;
mod slave;
mod wire;
pub(crate) use slave::NmtCore;
pub use slave::{NmtSlave, NmtSlaveEvent, ResetKind};
pub use wire::{
    error_control_id, guard_request, is_guard_request, Heartbeat, HeartbeatFrame, NmtCommand,
    NmtCommandSpecifier, NmtFrame, NmtTarget,
};

/// An NMT state as heartbeats and node-guarding replies report it (7 bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NmtState {
    /// 00h: boot-up (sent once, entering pre-operational).
    BootUp,
    /// 04h: stopped.
    Stopped,
    /// 05h: operational.
    Operational,
    /// 7Fh: pre-operational.
    PreOperational,
    /// Any other 7-bit value, kept.
    Unknown(u8),
}

impl NmtState {
    /// From the low 7 bits of `raw` (bit 7 is the toggle and is ignored here).
    #[must_use]
    #[inline]
    pub const fn from_bits(raw: u8) -> Self {
        // The four named values (0, 4, 5, 127) differ in their low three
        // bits: one slot each in an eight-entry table, the other slots
        // holding the unnamed values 1, 2, 3 and 6.
        let bits = raw & 0x7F;
        let slot = (bits & 7) as usize;
        if SLOT_BITS[slot] == bits {
            SLOT_STATES[slot]
        } else {
            NmtState::Unknown(bits)
        }
    }

    /// The state a 7-bit value names (CiA 301 section 7.2.8.3.2: 0
    /// boot-up, 4 stopped, 5 operational, 127 pre-operational).
    const fn named(bits: u8) -> Self {
        match bits {
            0x00 => NmtState::BootUp,
            0x04 => NmtState::Stopped,
            0x05 => NmtState::Operational,
            0x7F => NmtState::PreOperational,
            other => NmtState::Unknown(other),
        }
    }

    /// The 7-bit value.
    #[must_use]
    #[inline]
    pub const fn bits(self) -> u8 {
        match self {
            NmtState::BootUp => 0x00,
            NmtState::Stopped => 0x04,
            NmtState::Operational => 0x05,
            NmtState::PreOperational => 0x7F,
            NmtState::Unknown(raw) => raw & 0x7F,
        }
    }
}

/// The value of each slot of [`NmtState::from_bits`]'s table: the named
/// states where their low three bits put them, else the slot's number.
const SLOT_BITS: [u8; 8] = [0x00, 1, 2, 3, 0x04, 0x05, 6, 0x7F];

/// [`SLOT_BITS`] decoded.
const SLOT_STATES: [NmtState; 8] = {
    let mut t = [NmtState::BootUp; 8];
    let mut i = 0;
    while i < 8 {
        t[i] = NmtState::named(SLOT_BITS[i]);
        i += 1;
    }
    t
};

impl fmt::Display for NmtState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NmtState::BootUp => f.write_str("boot-up"),
            NmtState::Stopped => f.write_str("stopped"),
            NmtState::Operational => f.write_str("operational"),
            NmtState::PreOperational => f.write_str("pre-operational"),
            NmtState::Unknown(raw) => write!(f, "unknown state {raw:02X}h"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_state_byte_decodes_and_reencodes() {
        for raw in 0..=u8::MAX {
            let state = NmtState::from_bits(raw);
            assert_eq!(state.bits(), raw & 0x7F, "{raw:#04x}");
            let named = matches!(raw & 0x7F, 0x00 | 0x04 | 0x05 | 0x7F);
            assert_eq!(!matches!(state, NmtState::Unknown(_)), named, "{raw:#04x}");
        }
    }
}
