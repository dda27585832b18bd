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

use core::fmt;

use crate::cob_id::NodeId;
use crate::error::{exact_len, DecodeError};

pub mod guarding;
pub mod heartbeat;
mod slave;
pub use heartbeat::Heartbeat;
pub(crate) use slave::NmtCore;
pub use slave::{NmtSlave, NmtSlaveEvent, ResetKind};

/// NMT command specifier (byte 0 of an NMT frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NmtCommandSpecifier {
    /// 01h: start remote node (enter operational).
    Start,
    /// 02h: stop remote node (enter stopped).
    Stop,
    /// 80h: enter pre-operational.
    EnterPreOperational,
    /// 81h: reset node.
    ResetNode,
    /// 82h: reset communication.
    ResetCommunication,
    /// Any other byte, kept.
    Unknown(u8),
}

impl From<u8> for NmtCommandSpecifier {
    fn from(raw: u8) -> Self {
        match raw {
            0x01 => Self::Start,
            0x02 => Self::Stop,
            0x80 => Self::EnterPreOperational,
            0x81 => Self::ResetNode,
            0x82 => Self::ResetCommunication,
            other => Self::Unknown(other),
        }
    }
}

impl From<NmtCommandSpecifier> for u8 {
    fn from(cs: NmtCommandSpecifier) -> u8 {
        match cs {
            NmtCommandSpecifier::Start => 0x01,
            NmtCommandSpecifier::Stop => 0x02,
            NmtCommandSpecifier::EnterPreOperational => 0x80,
            NmtCommandSpecifier::ResetNode => 0x81,
            NmtCommandSpecifier::ResetCommunication => 0x82,
            NmtCommandSpecifier::Unknown(raw) => raw,
        }
    }
}

impl fmt::Display for NmtCommandSpecifier {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Start => f.write_str("start"),
            Self::Stop => f.write_str("stop"),
            Self::EnterPreOperational => f.write_str("enter pre-operational"),
            Self::ResetNode => f.write_str("reset node"),
            Self::ResetCommunication => f.write_str("reset communication"),
            Self::Unknown(raw) => write!(f, "unknown command {raw:02X}h"),
        }
    }
}

/// The node(s) an NMT command addresses (byte 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NmtTarget {
    /// 0: every node.
    All,
    /// 1..=127: one node.
    Node(NodeId),
    /// 128..=255: not a node id; kept so the frame round-trips.
    Invalid(u8),
}

impl From<u8> for NmtTarget {
    fn from(raw: u8) -> Self {
        match (raw, NodeId::new(raw)) {
            (0, _) => NmtTarget::All,
            (_, Some(n)) => NmtTarget::Node(n),
            (other, None) => NmtTarget::Invalid(other),
        }
    }
}

impl From<NmtTarget> for u8 {
    fn from(t: NmtTarget) -> u8 {
        match t {
            NmtTarget::All => 0,
            NmtTarget::Node(n) => n.raw(),
            NmtTarget::Invalid(raw) => raw,
        }
    }
}

impl NmtTarget {
    /// True if a node with id `node` must obey a command with this target.
    #[must_use]
    pub fn addresses(self, node: NodeId) -> bool {
        match self {
            NmtTarget::All => true,
            NmtTarget::Node(n) => n == node,
            NmtTarget::Invalid(_) => false,
        }
    }
}

/// An NMT module-control command.
///
/// ```
/// use canopen_codec::nmt::{NmtCommand, NmtCommandSpecifier, NmtTarget};
/// use canopen_codec::NodeId;
/// // The real capture's `000#010A`: start node 10.
/// let cmd = NmtCommand::decode(&[0x01, 0x0A]).unwrap();
/// assert_eq!(cmd.command, NmtCommandSpecifier::Start);
/// assert_eq!(cmd.target, NmtTarget::Node(NodeId::new(10).unwrap()));
/// assert_eq!(cmd.encode(), [0x01, 0x0A]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NmtCommand {
    /// What to do.
    pub command: NmtCommandSpecifier,
    /// Who does it.
    pub target: NmtTarget,
}

impl NmtCommand {
    /// Decodes the 2 data bytes of an NMT frame.
    #[inline]
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        exact_len(data, 2)?;
        let [cs, node] = *data else {
            return Err(DecodeError::Truncated {
                need: 2,
                got: data.len(),
            });
        };
        Ok(NmtCommand {
            command: cs.into(),
            target: node.into(),
        })
    }

    /// The 2 data bytes.
    #[must_use]
    #[inline]
    pub fn encode(&self) -> [u8; 2] {
        [self.command.into(), self.target.into()]
    }
}

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

    #[test]
    fn public_vectors_n1_n2_n3() {
        let n1 = NodeId::new(1).unwrap();
        // [N1] start node 1, then operational heartbeat.
        let start = NmtCommand::decode(&[0x01, 0x01]).unwrap();
        assert_eq!(start.command, NmtCommandSpecifier::Start);
        assert_eq!(start.target, NmtTarget::Node(n1));
        assert_eq!(
            Heartbeat::decode(&[0x05]).unwrap().state,
            NmtState::Operational
        );
        // [N2] reset communication node 1, boot-up.
        let rc = NmtCommand::decode(&[0x82, 0x01]).unwrap();
        assert_eq!(rc.command, NmtCommandSpecifier::ResetCommunication);
        assert!(Heartbeat::decode(&[0x00]).unwrap().is_boot_up());
        // [N3] all nodes pre-operational.
        let pre = NmtCommand::decode(&[0x80, 0x00]).unwrap();
        assert_eq!(pre.command, NmtCommandSpecifier::EnterPreOperational);
        assert_eq!(pre.target, NmtTarget::All);
        assert!(pre.target.addresses(n1));
    }

    #[test]
    fn every_command_and_target_byte_round_trips() {
        for cs in 0..=255u8 {
            for node in [0u8, 1, 10, 127, 128, 255] {
                let cmd = NmtCommand::decode(&[cs, node]).unwrap();
                assert_eq!(cmd.encode(), [cs, node]);
            }
        }
        assert_eq!(
            NmtCommandSpecifier::from(0x81),
            NmtCommandSpecifier::ResetNode
        );
        assert_eq!(
            NmtCommandSpecifier::from(0x03),
            NmtCommandSpecifier::Unknown(0x03)
        );
        assert_eq!(NmtTarget::from(200), NmtTarget::Invalid(200));
        assert!(!NmtTarget::Invalid(200).addresses(NodeId::MIN));
    }

    #[test]
    fn every_heartbeat_byte_round_trips() {
        for b in 0..=255u8 {
            assert_eq!(Heartbeat::from_byte(b).encode(), b);
        }
        assert_eq!(NmtState::from_bits(0x04), NmtState::Stopped);
        assert_eq!(NmtState::from_bits(0x06), NmtState::Unknown(0x06));
    }

    #[test]
    fn lengths() {
        crate::error::assert_exact_length(NmtCommand::decode, 2);
        crate::error::assert_exact_length(Heartbeat::decode, 1);
    }
}
